/* draw.c -- the view's drawing thread: the newest state of the mailbox
 * rendered (OSMesa, render_frame, the head-up strip included) into the
 * image the window does not show, then handed over (the two images
 * swapped under the mutex) and the window woken by an SDL user event. A
 * state that arrives while a frame is drawn waits in the mailbox, replaced
 * by any newer one: the thread draws as fast as it can, never a stale
 * state after a newer one, and never makes the receive thread or the
 * station's loop wait. A run_info_t from the loop opens its scene here
 * (this thread alone touches the scene and its seaway). */
#include "otw_priv.h"

#include <SDL.h>
#include <math.h>
#include <string.h>

/* The loop's run information (newer than the scene's): the scene it names,
 * or the old one kept with the reason counted as a refusal. Under mu. */
static void take_run_info(otw *w)
{
    sim_run_info ri = w->run_info;
    pthread_mutex_unlock(&w->mu);
    otw_scene fresh;
    core_err e = {0};
    int rc = otw_scene_open(&fresh, &ri, w->o.overlays, &e);
    if (rc == 0) {
        otw_scene_close(&w->scene);
        w->scene = fresh;
        otw_scene_moved(&w->scene);
    } else {
        otw_scene_close(&fresh);
    }
    pthread_mutex_lock(&w->mu);
    w->scene_ready = w->scene.open;
    if (rc != 0) {
        w->bad_rx++;
        snprintf(w->bad_last, sizeof w->bad_last, "run_info_t: %.200s", e.msg);
    }
}

/* Draw s from camera cam into img: 0, or < 0 with err. */
static int draw_one(otw *w, render_ctx *rc, render_state *s, render_camera_kind cam, const char *stats,
                    uint8_t *img, double t[2], core_err *err)
{
    otw_scene *sc = &w->scene;
    s->rotor_azimuth_rad = render_rotor_azimuth(&sc->run.geom, s->t_s);
    render_view v;
    if (render_camera_place(cam, &sc->sc, s, &v, err) != 0) {
        if (cam != RENDER_CAM_PILOT || sc->run.geom.has_eye)
            return -1;
        /* an aircraft file without the pilot's eye: the chase camera */
        cam = RENDER_CAM_CHASE;
        atomic_store(&w->camera, (int)cam);
        if (render_camera_place(cam, &sc->sc, s, &v, err) != 0)
            return -1;
    }
    snprintf(sc->title, sizeof sc->title, "%s%s%s  %s", stats, stats[0] ? "  " : "", render_camera_name(cam),
             sc->run.name);
    t[0] = core_monotonic_s();
    int rc_ = render_frame(rc, &sc->sc, s, &v, img, err);
    t[1] = core_monotonic_s();
    return rc_;
}

void *otw_draw_main(void *arg)
{
    otw *w = arg;
    core_err e = {0};
    render_ctx *rc = render_create(w->o.image_width, w->o.image_height, &e);
    long done_seq = 0, drawn_seq = 0, seen_ri = 0, done_redraw = 0;
    pthread_mutex_lock(&w->mu);
    if (!rc) {
        w->draw_failed = 1;
        w->draw_err = e;
    }
    while (rc && !atomic_load(&w->stop)) {
        if (w->run_info_seq != seen_ri) {
            seen_ri = w->run_info_seq;
            take_run_info(w);
            done_seq = 0; /* the newest state again, in the new scene */
            continue;
        }
        int redraw = w->redraw != done_redraw;
        if (!w->scene.open || w->slot_seq == 0 || (w->slot_seq == done_seq && !redraw)) {
            pthread_cond_wait(&w->cv, &w->mu);
            continue;
        }
        render_state s = w->slot;
        long seq = w->slot_seq;
        /* a state drawn again (the camera changed, a new scene): its age is not a latency */
        double arrival = seq == drawn_seq ? NAN : w->slot_arrival_s;
        done_seq = drawn_seq = seq;
        done_redraw = w->redraw;
        render_camera_kind cam = (render_camera_kind)atomic_load(&w->camera);
        char stats[sizeof w->hud_stats];
        memcpy(stats, w->hud_stats, sizeof stats);
        int back = 1 - w->front;
        pthread_mutex_unlock(&w->mu);
        double t[2] = {0.0, 0.0};
        int r = draw_one(w, rc, &s, cam, stats, w->img[back], t, &e);
        pthread_mutex_lock(&w->mu);
        if (r != 0) {
            w->draw_failed = 1;
            w->draw_err = e;
            break;
        }
        w->front = back;
        w->fresh = 1;
        w->front_seq = seq;
        w->front_arrival_s = arrival;
        w->front_draw0_s = t[0];
        w->front_draw1_s = t[1];
        w->front_t_s = s.t_s;
        w->frames_drawn++;
        otw_samples_add(&w->draw_s, t[1] - t[0]);
        SDL_Event ev;
        memset(&ev, 0, sizeof ev);
        ev.type = w->ev_frame;
        SDL_PushEvent(&ev);
    }
    if (w->draw_failed) {
        SDL_Event ev;
        memset(&ev, 0, sizeof ev);
        ev.type = w->ev_frame;
        SDL_PushEvent(&ev);
    }
    pthread_mutex_unlock(&w->mu);
    render_destroy(rc);
    return NULL;
}
