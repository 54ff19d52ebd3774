/* window.c -- the view's window (SDL2) on the caller's thread: the frames
 * of the drawing thread put on screen through a streaming texture
 * (SDL_UpdateTexture, SDL_RenderCopy, SDL_RenderPresent), the window's
 * keys and the game controllers (SDL's game-controller API and mapping
 * database) turned into the station's controls on the input pipe, the
 * frame rate and latency measured and shown in the head-up strip's top
 * line (the last 60 frames shown, updated twice a second), and the
 * station's loop run beside it in a thread of its own. */
#define _GNU_SOURCE /* pipe2 */
#include "otw_priv.h"

#include <SDL.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define HUD_LAST_FRAMES 60
#define TAKE_OVER_HOLD_S 0.25 /* the take-over key held this long: a few messages of any station rate */

void otw_opts_default(otw_opts *o)
{
    memset(o, 0, sizeof *o);
    o->camera = RENDER_CAM_PILOT;
    o->width = 1280;
    o->height = 720;
    o->overlays = RENDER_OVERLAY_HUD;
    o->step_pct = 2.0;
}

otw *otw_create(const otw_opts *o, core_err *err)
{
    int iw = o->image_width > 0 ? o->image_width : o->width, ih = o->image_height > 0 ? o->image_height : o->height;
    if (o->width < RENDER_SIZE_MIN || o->height < RENDER_SIZE_MIN || o->width > RENDER_SIZE_MAX ||
        o->height > RENDER_SIZE_MAX || iw < RENDER_SIZE_MIN || ih < RENDER_SIZE_MIN || iw > RENDER_SIZE_MAX ||
        ih > RENDER_SIZE_MAX || (int)o->camera < 0 || o->camera >= RENDER_CAM_COUNT) {
        core_err_set(err, -1, "view: size %dx%d, image %dx%d or camera %d out of range", o->width, o->height, iw, ih,
                     (int)o->camera);
        return NULL;
    }
    otw *w = calloc(1, sizeof *w);
    if (!w) {
        core_err_set(err, -1, "view: out of memory");
        return NULL;
    }
    w->o = *o;
    w->o.image_width = iw;
    w->o.image_height = ih;
    w->in_pipe[0] = w->in_pipe[1] = -1;
    pthread_mutex_init(&w->mu, NULL);
    pthread_cond_init(&w->cv, NULL);
    atomic_init(&w->stop, 0);
    atomic_init(&w->camera, (int)o->camera);
    size_t bytes = (size_t)4 * (size_t)iw * (size_t)ih;
    if (!(w->img[0] = calloc(1, bytes)) || !(w->img[1] = calloc(1, bytes))) {
        core_err_set(err, -1, "view: out of memory");
        otw_destroy(w);
        return NULL;
    }
    if (o->scenario_path) {
        sim_scenario *sc = calloc(1, sizeof *sc);
        sim_world_overrides ov;
        sim_world_overrides_default(&ov);
        sim_run_info ri;
        int rc = sc ? sim_scenario_load(o->scenario_path, sc, err) : core_err_set(err, -1, "view: out of memory");
        if (rc == 0) {
            sim_world_run_info(sc, &ov, &ri);
            rc = otw_scene_open(&w->scene, &ri, o->overlays, err);
        }
        free(sc);
        w->scene_ready = rc == 0;
        if (rc != 0) {
            otw_destroy(w);
            return NULL;
        }
    }
    if (o->inputs && (pipe2(w->in_pipe, O_CLOEXEC) != 0 || fcntl(w->in_pipe[1], F_SETFL, O_NONBLOCK) != 0)) {
        core_err_set(err, -1, "view: input pipe: %s", strerror(errno));
        otw_destroy(w);
        return NULL;
    }
    if (o->stats_path && !(w->stats = fopen(o->stats_path, "w"))) {
        core_err_set(err, -1, "view: %s: %s", o->stats_path, strerror(errno));
        otw_destroy(w);
        return NULL;
    }
    if (w->stats)
        fprintf(w->stats, "frame,t_s,arrival_s,draw_start_s,draw_end_s,upload_s,present_s,shown_s,latency_s\n");
    if (otw_rx_start(w, err) != 0) {
        otw_destroy(w);
        return NULL;
    }
    return w;
}

int otw_input_fd(const otw *w) { return w->in_pipe[0]; }

/* ------------------------------------------------------------ the window */
typedef struct win {
    otw *w;
    SDL_Window *win;
    SDL_Renderer *ren;
    SDL_Texture *tex;
    SDL_GameController *pad;
    SDL_JoystickID pad_id;
    otw_pad_map map;
    sim_station_controls ctl;
    int dirty, moved, synced, quit;
    double take_over_until, t0, hud_t, hud_frames;
    int (*body)(void *);
    void *arg;
    int body_rc;
    atomic_int body_done;
    uint32_t ev_done;
} win;

static int body_main(void *arg)
{
    win *x = arg;
    x->body_rc = x->body(x->arg);
    atomic_store(&x->body_done, 1);
    SDL_Event ev;
    memset(&ev, 0, sizeof ev);
    ev.type = x->ev_done;
    SDL_PushEvent(&ev);
    return 0;
}

static void set_title(win *x)
{
    char t[160];
    render_camera_kind cam = (render_camera_kind)atomic_load(&x->w->camera);
    pthread_mutex_lock(&x->w->mu);
    int scene = x->w->scene_ready;
    pthread_mutex_unlock(&x->w->mu);
    snprintf(t, sizeof t, "disim station: %s camera%s%s", render_camera_name(cam),
             scene ? "" : " (waiting for the loop's run_info_t)", x->pad ? " (game controller)" : "");
    SDL_SetWindowTitle(x->win, t);
}

static void ask_quit(win *x)
{
    if (!x->quit && x->w->o.quit)
        x->w->o.quit(x->w->o.quit_user);
    x->quit = 1;
}

static void camera_changed(win *x)
{
    pthread_mutex_lock(&x->w->mu);
    x->w->redraw++;
    pthread_cond_broadcast(&x->w->cv);
    pthread_mutex_unlock(&x->w->mu);
    set_title(x);
}

static void on_key(win *x, int sym)
{
    render_camera_kind cam = (render_camera_kind)atomic_load(&x->w->camera);
    sim_station_controls c = x->ctl;
    int r = otw_keys_feed(sym, x->w->o.step_pct, &c, &cam);
    if (r == OTW_KEY_CAMERA) {
        atomic_store(&x->w->camera, (int)cam);
        camera_changed(x);
    } else if (r == OTW_KEY_QUIT) {
        ask_quit(x);
    } else if (x->w->o.inputs && r == OTW_KEY_MOVED) {
        x->ctl = c;
        x->dirty = x->moved = 1;
    } else if (x->w->o.inputs && r == OTW_KEY_TAKE_OVER) {
        x->ctl.take_over = 1;
        x->take_over_until = core_monotonic_s() + TAKE_OVER_HOLD_S;
        x->dirty = 1;
    }
}

static void on_pad(win *x, const SDL_Event *e)
{
    if (e->type == SDL_CONTROLLERDEVICEADDED && !x->pad) {
        if ((x->pad = SDL_GameControllerOpen(e->cdevice.which)))
            x->pad_id = SDL_JoystickInstanceID(SDL_GameControllerGetJoystick(x->pad));
        set_title(x);
    } else if (e->type == SDL_CONTROLLERDEVICEREMOVED && x->pad && e->cdevice.which == x->pad_id) {
        SDL_GameControllerClose(x->pad);
        x->pad = NULL;
        set_title(x);
    } else if (x->w->o.inputs && e->type == SDL_CONTROLLERAXISMOTION && x->pad && e->caxis.which == x->pad_id) {
        if (otw_pad_axis(&x->map, e->caxis.axis, e->caxis.value, &x->ctl))
            x->dirty = x->moved = 1;
    } else if (x->w->o.inputs && (e->type == SDL_CONTROLLERBUTTONDOWN || e->type == SDL_CONTROLLERBUTTONUP) &&
               x->pad && e->cbutton.which == x->pad_id) {
        if (otw_pad_button(&x->map, e->cbutton.button, e->type == SDL_CONTROLLERBUTTONDOWN, &x->ctl))
            x->dirty = 1;
    }
}

static void on_event(win *x, const SDL_Event *e)
{
    if (e->type == SDL_QUIT)
        ask_quit(x);
    else if (e->type == SDL_KEYDOWN)
        on_key(x, e->key.keysym.sym);
    else if (e->type >= SDL_CONTROLLERAXISMOTION && e->type <= SDL_CONTROLLERDEVICEREMAPPED)
        on_pad(x, e);
}

/* The controls to the station: the pipe carries spring-centred sticks
 * (sim/station.c's force trim flies them as deflections about the
 * reference it took from the flight), so the window's axes start at their
 * centre (50 %: no deflection) and the keys and a controller's sticks move
 * deflections; the take-over released after its hold, written when
 * changed (kept dirty while the pipe is full). */
static void send_controls(win *x, double now)
{
    otw *w = x->w;
    if (!w->o.inputs)
        return;
    if (!x->synced && !x->moved) {
        x->ctl.ctl.collective_pct = x->ctl.ctl.long_cyclic_pct = 50.0;
        x->ctl.ctl.lat_cyclic_pct = x->ctl.ctl.pedal_pct = 50.0;
        x->synced = x->dirty = 1;
    }
    if (x->ctl.take_over && x->take_over_until > 0.0 && now >= x->take_over_until) {
        x->ctl.take_over = 0;
        x->take_over_until = 0.0;
        x->dirty = 1;
    }
    if (x->dirty && otw_input_write(w->in_pipe[1], &x->ctl) == 0)
        x->dirty = 0;
}

/* The figures for the strip: the frame rate since the last update, the
 * latency of the last frames. */
static void hud_update(win *x, double now)
{
    otw *w = x->w;
    if (now - x->hud_t < 0.5)
        return;
    double fps = (w->frames_shown - x->hud_frames) / (now - x->hud_t);
    double p50 = otw_samples_quantile(&w->latency_s, HUD_LAST_FRAMES, 0.5);
    double p99 = otw_samples_quantile(&w->latency_s, HUD_LAST_FRAMES, 0.99);
    pthread_mutex_lock(&w->mu);
    if (isfinite(p50))
        snprintf(w->hud_stats, sizeof w->hud_stats, "%.0f fps  lat p50 %.0f p99 %.0f ms", fps, 1e3 * p50,
                 1e3 * p99);
    else
        snprintf(w->hud_stats, sizeof w->hud_stats, "%.0f fps", fps);
    pthread_mutex_unlock(&w->mu);
    x->hud_t = now;
    x->hud_frames = (double)w->frames_shown;
}

/* A fresh frame on screen, its latency measured. 0, 1 none fresh, < 0 with err. */
static int show_frame(win *x, core_err *err)
{
    otw *w = x->w;
    double t_up = core_monotonic_s();
    pthread_mutex_lock(&w->mu);
    if (!w->fresh) {
        pthread_mutex_unlock(&w->mu);
        return 1;
    }
    int r = SDL_UpdateTexture(x->tex, NULL, w->img[w->front], 4 * w->o.image_width);
    w->fresh = 0;
    double arrival = w->front_arrival_s, d0 = w->front_draw0_s, d1 = w->front_draw1_s, t_s = w->front_t_s;
    pthread_mutex_unlock(&w->mu);
    if (r != 0 || SDL_RenderCopy(x->ren, x->tex, NULL, NULL) != 0)
        return core_err_set(err, -1, "view: SDL: %s", SDL_GetError());
    double t_pr = core_monotonic_s();
    SDL_RenderPresent(x->ren);
    double now = core_monotonic_s();
    if (w->frames_shown++ == 0)
        w->first_shown_s = now;
    w->last_shown_s = now;
    if (isfinite(arrival))
        otw_samples_add(&w->latency_s, now - arrival);
    if (w->stats) {
        double z = x->t0;
        fprintf(w->stats, "%ld,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f\n", w->frames_shown, t_s, arrival - z, d0 - z,
                d1 - z, t_up - z, t_pr - z, now - z, isfinite(arrival) ? now - arrival : NAN);
    }
    hud_update(x, now);
    return 0;
}

static int window_open(win *x, core_err *err)
{
    otw *w = x->w;
    SDL_SetHint(SDL_HINT_NO_SIGNAL_HANDLERS, "1");
    if (SDL_Init(SDL_INIT_VIDEO) != 0)
        return core_err_set(err, -1, "view: no window: %s (a display: DISPLAY, or xvfb-run)", SDL_GetError());
    /* SDL falls back on drivers that show nothing: only when asked for by name */
    const char *drv = SDL_GetCurrentVideoDriver(), *asked = getenv("SDL_VIDEODRIVER");
    if (drv && (!strcmp(drv, "offscreen") || !strcmp(drv, "dummy")) && !(asked && !strcmp(asked, drv)))
        return core_err_set(err, -1, "view: no window: no display (DISPLAY or WAYLAND_DISPLAY; xvfb-run without "
                                     "one), SDL found only its '%s' driver", drv);
    if (SDL_InitSubSystem(SDL_INIT_GAMECONTROLLER) == 0 && w->o.pad_mappings &&
        SDL_GameControllerAddMappingsFromFile(w->o.pad_mappings) < 0)
        return core_err_set(err, -1, "view: %s: %s", w->o.pad_mappings, SDL_GetError());
    x->win = SDL_CreateWindow("disim station", SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, w->o.width,
                              w->o.height, 0);
    if (!x->win || !(x->ren = SDL_CreateRenderer(x->win, -1, 0)))
        return core_err_set(err, -1, "view: SDL window: %s", SDL_GetError());
    SDL_RendererInfo ri;
    if (SDL_GetRendererInfo(x->ren, &ri) == 0)
        snprintf(w->renderer, sizeof w->renderer, "%s", ri.name);
    SDL_SetHint(SDL_HINT_RENDER_SCALE_QUALITY, "linear"); /* an image smaller than the window */
    x->tex = SDL_CreateTexture(x->ren, SDL_PIXELFORMAT_RGBA32, SDL_TEXTUREACCESS_STREAMING, w->o.image_width,
                               w->o.image_height);
    if (!x->tex)
        return core_err_set(err, -1, "view: SDL texture: %s", SDL_GetError());
    uint32_t ev = SDL_RegisterEvents(2);
    if (ev == (uint32_t)-1)
        return core_err_set(err, -1, "view: SDL: no user events left");
    w->ev_frame = ev;
    x->ev_done = ev + 1;
    SDL_SetRenderDrawColor(x->ren, 40, 44, 52, 255);
    SDL_RenderClear(x->ren);
    SDL_RenderPresent(x->ren);
    set_title(x);
    return 0;
}

static void window_close(win *x)
{
    if (x->pad)
        SDL_GameControllerClose(x->pad);
    if (x->tex)
        SDL_DestroyTexture(x->tex);
    if (x->ren)
        SDL_DestroyRenderer(x->ren);
    if (x->win)
        SDL_DestroyWindow(x->win);
    /* No SDL_Quit: it unloads the X11 and GL libraries SDL loaded, which
     * leave allocations behind (LeakSanitizer shows them from an unknown
     * module); the process's exit releases them, the window is gone. */
}

/* Events, frames and controls until the body is done. */
static int window_loop(win *x, core_err *err)
{
    otw *w = x->w;
    int rc = 0;
    while (!atomic_load(&x->body_done)) {
        double now = core_monotonic_s();
        int wait_ms = w->o.inputs && !x->synced && !x->moved ? 10 : 100; /* the first state soon taken */
        if (x->take_over_until > 0.0)
            wait_ms = (int)fmax(1.0, fmin(100.0, 1e3 * (x->take_over_until - now)));
        SDL_Event e;
        if (SDL_WaitEventTimeout(&e, wait_ms)) {
            on_event(x, &e);
            while (SDL_PollEvent(&e))
                on_event(x, &e);
        }
        send_controls(x, core_monotonic_s());
        pthread_mutex_lock(&w->mu);
        int failed = w->draw_failed;
        pthread_mutex_unlock(&w->mu);
        if (failed) {
            *err = w->draw_err;
            rc = -1;
            break;
        }
        if (rc == 0 && show_frame(x, err) < 0) {
            rc = -1;
            break;
        }
    }
    return rc;
}

int otw_run(otw *w, int (*body)(void *arg), void *arg, int *body_rc, core_err *err)
{
    win *x = calloc(1, sizeof *x);
    if (!x)
        return core_err_set(err, -1, "view: out of memory");
    x->w = w;
    x->body = body;
    x->arg = arg;
    x->t0 = x->hud_t = core_monotonic_s();
    atomic_init(&x->body_done, 0);
    otw_pad_map_default(&x->map);
    sim_station_controls_centre(&x->ctl);
    int rc = window_open(x, err);
    if (rc == 0 && pthread_create(&w->draw_th, NULL, otw_draw_main, w) != 0)
        rc = core_err_set(err, -1, "view: cannot start the drawing thread");
    w->draw_started = rc == 0;
    SDL_Thread *bt = rc == 0 ? SDL_CreateThread(body_main, "station", x) : NULL;
    if (rc == 0 && !bt)
        rc = core_err_set(err, -1, "view: cannot start the station's thread: %s", SDL_GetError());
    if (rc == 0) {
        rc = window_loop(x, err);
        if (rc != 0)
            ask_quit(x);
        SDL_WaitThread(bt, NULL);
        *body_rc = x->body_rc;
    }
    atomic_store(&w->stop, 1);
    pthread_mutex_lock(&w->mu);
    pthread_cond_broadcast(&w->cv);
    pthread_mutex_unlock(&w->mu);
    if (w->draw_started)
        pthread_join(w->draw_th, NULL);
    w->draw_started = 0;
    window_close(x);
    free(x);
    return rc;
}

void otw_get_report(const otw *w, otw_report *r)
{
    memset(r, 0, sizeof *r);
    otw *m = (otw *)w; /* the mutex only */
    pthread_mutex_lock(&m->mu);
    r->states = w->states;
    r->frames_drawn = w->frames_drawn;
    r->bad_rx = w->bad_rx;
    snprintf(r->bad_last, sizeof r->bad_last, "%s", w->bad_last);
    r->draw_p50_s = otw_samples_quantile(&w->draw_s, 0, 0.5);
    r->draw_p99_s = otw_samples_quantile(&w->draw_s, 0, 0.99);
    pthread_mutex_unlock(&m->mu);
    r->frames_shown = w->frames_shown;
    r->seconds = w->frames_shown > 1 ? w->last_shown_s - w->first_shown_s : 0.0;
    r->fps = r->seconds > 0.0 ? (double)(w->frames_shown - 1) / r->seconds : 0.0;
    r->latency_p50_s = otw_samples_quantile(&w->latency_s, 0, 0.5);
    r->latency_p99_s = otw_samples_quantile(&w->latency_s, 0, 0.99);
    r->latency_max_s = otw_samples_quantile(&w->latency_s, 0, 1.0);
    snprintf(r->renderer, sizeof r->renderer, "%s", w->renderer);
}

void otw_destroy(otw *w)
{
    if (!w)
        return;
    otw_rx_stop(w);
    otw_scene_close(&w->scene);
    for (int i = 0; i < 2; i++)
        if (w->in_pipe[i] >= 0)
            close(w->in_pipe[i]);
    if (w->stats)
        fclose(w->stats);
    otw_samples_free(&w->draw_s);
    otw_samples_free(&w->latency_s);
    free(w->img[0]);
    free(w->img[1]);
    pthread_cond_destroy(&w->cv);
    pthread_mutex_destroy(&w->mu);
    free(w);
}
