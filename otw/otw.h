/*
 * otw.h -- the out-the-window view at the pilot station (`disim station
 * --view`): a window (SDL2) showing what a camera sees (render/: the
 * pilot's eye, the deck, chase or overhead camera) with the head-up strip
 * over it, drawn from the heli_state_t and ship_state_t the station
 * receives on LCM, as an image generator is fed by a flight model; the
 * window's keys and SDL game controllers (SDL's mapping database) as the
 * station's controls.
 *
 * Threads. The caller's thread runs SDL (the window, its events, the
 * texture and the present); a receive thread of its own takes the states
 * from LCM (its own LCM instance), stamps their arrival (CLOCK_MONOTONIC)
 * and puts the newest in a mailbox; a drawing thread renders the newest
 * state with OSMesa (render_frame) into one of two images and hands it to
 * the window; the station's publishing loop runs in a thread the window
 * starts (otw_run). No thread waits on another's work: a slow frame never
 * delays the messages the station publishes, a state that arrives while a
 * frame is drawn replaces the one waiting.
 *
 * Inputs. The window's inputs reach the station as an evdev device would:
 * a pipe of struct input_event (otw_input_fd) that the station reads with
 * sim_station_evdev_wrap and the axes of otw_input_axes (each control as
 * an absolute axis 0 to 10000, a hundredth of a percent; the trim and
 * take-over as the buttons the evdev default uses). The game controller's
 * sticks and the keys are mapped to the four controls in percent of travel
 * (docs/conventions.md) by otw_pad_pct and otw_keys_feed.
 *
 * Latency: from a state's arrival (the first of the step's heli_state_t and
 * ship_state_t, stamped in the receive thread) to the return of
 * SDL_RenderPresent for the frame drawn from it; p50 and p99 over the
 * frames shown in the strip's top line (the last 2 s) and in the report
 * (all frames).
 */
#ifndef DISIM_OTW_H
#define DISIM_OTW_H

#include "core.h"
#include "render.h"
#include "sim.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* -------------------------------------------------- the controller mapping */
/* A game controller's stick axis (SDL: -32768 to 32767, up and left
 * negative) in percent of travel: a dead band of dead_frac of the half
 * travel around the centre reads 50 %, the rest stretched to the stops
 * (no step at its edge), clamped to 0..100, 100 - pct when invert. */
double otw_pad_pct(int value, double dead_frac, int invert);

/* The helicopter layout on a game controller (as the evdev default of the
 * station): left stick up/down the collective (up = more), left stick
 * left/right the pedals, right stick the cyclic (forward = 0 %, left =
 * 0 %); the shoulders the force-trim set (left) and release (right),
 * START (held) takes the controls over. Axes and buttons are SDL's
 * SDL_GameControllerAxis and SDL_GameControllerButton numbers. */
typedef struct otw_pad_map {
    int axis[SIM_AXES];             /* SDL axis of each control (SIM_AXIS_*), -1: none */
    int invert[SIM_AXES];
    int trim_button, trim_release, take_over; /* SDL buttons, -1: none */
    double dead_frac;               /* 0.1 */
} otw_pad_map;
void otw_pad_map_default(otw_pad_map *m);
/* An axis's new value into c: 1 if it is one of the controls', else 0. */
int otw_pad_axis(const otw_pad_map *m, int axis, int value, sim_station_controls *c);
/* A button pressed (1) or released (0) into c: 1 if mapped, else 0. */
int otw_pad_button(const otw_pad_map *m, int button, int down, sim_station_controls *c);

/* ------------------------------------------------------- keys in the window */
/* The terminal's keys (sim_station_keys_feed) in the window: w / s the
 * collective, the arrows the cyclic, a / d the pedals by step_pct per press
 * (and per auto-repeat), space centres the cyclic and the pedals, t takes
 * the controls over; c cycles the camera, 1 to 4 choose it (pilot, deck,
 * chase, overhead); q and Escape quit. */
enum { OTW_KEY_NONE = 0, OTW_KEY_MOVED = 1, OTW_KEY_TAKE_OVER = 2, OTW_KEY_CAMERA = 3, OTW_KEY_QUIT = 4 };
/* sym: an SDL_Keycode. OTW_KEY_* ; *camera set for OTW_KEY_CAMERA. */
int otw_keys_feed(int sym, double step_pct, sim_station_controls *c, render_camera_kind *camera);

/* ----------------------------------------------------- the input device */
/* The axes of the window's input pipe (codes ABS_X, ABS_Y, ABS_RX, ABS_RY
 * for collective, long, lat, pedal; 0 to 10000; BTN_TL, BTN_TR, BTN_START). */
void otw_input_axes(sim_station_axes *a);
/* c as events on fd (a write end): each control, the three buttons, a
 * SYN_REPORT. 0, or -1 when the pipe is closed or full. */
int otw_input_write(int fd, const sim_station_controls *c);

/* --------------------------------------------------------------- the view */
typedef struct otw_opts {
    const char *scenario_path;  /* the scene before the loop's run_info_t (NULL: wait for it) */
    const char *lcm_url;        /* NULL: the LCM library's default */
    render_camera_kind camera;  /* RENDER_CAM_PILOT (the chase camera for an aircraft file without the pilot's eye) */
    int width, height;          /* the window (1280 x 720) */
    int image_width, image_height; /* the image drawn, scaled to the window (linear); 0: the window's */
    unsigned overlays;          /* RENDER_OVERLAY_HUD */
    int inputs;                 /* 1: the window's keys and game controllers fly (otw_input_fd) */
    double step_pct;            /* a key press (2) */
    const char *pad_mappings;   /* a gamecontrollerdb.txt added to SDL's own, or NULL */
    const char *stats_path;     /* a CSV of every frame shown, or NULL: frame, t_s (the state's
                                   simulation time), then seconds since the view started: the
                                   state's arrival, the drawing's start and end, the texture's
                                   upload, SDL_RenderPresent's call and return (shown); latency_s */
    void (*quit)(void *user);   /* the window asks the station to stop (closed, q) */
    void *quit_user;
} otw_opts;
void otw_opts_default(otw_opts *o);

typedef struct otw otw;
/* The view's parts that need no window: the scene (scenario_path), the
 * receive thread, the input pipe. NULL with err. */
otw *otw_create(const otw_opts *o, core_err *err);
/* The read end of the input pipe (the view keeps it open; the station wraps
 * a dup of it); -1 without inputs. */
int otw_input_fd(const otw *w);
/* The window on the calling thread until it is closed or body (the
 * station's loop, run in a thread of its own) returns; body's value in
 * *body_rc. 0, or < 0 with err (no display, SDL failed, a frame failed):
 * body has then not run, or has been asked to stop (quit) and joined. */
int otw_run(otw *w, int (*body)(void *arg), void *arg, int *body_rc, core_err *err);

typedef struct otw_report {
    long states;                 /* states received (heli and ship of a step) */
    long frames_drawn, frames_shown;
    double seconds;              /* from the first frame shown to the last */
    double fps;                  /* frames shown per second over that */
    double latency_p50_s, latency_p99_s, latency_max_s;
    double draw_p50_s, draw_p99_s; /* render_frame alone */
    long bad_rx;                 /* messages refused */
    char bad_last[256];
    char renderer[64];           /* SDL's renderer ("opengl", "software" ...) */
} otw_report;
void otw_get_report(const otw *w, otw_report *r);
void otw_destroy(otw *w);

#ifdef __cplusplus
}
#endif
#endif
