/*
 * render.h -- off-screen views of the dynamic interface (OSMesa, software
 * OpenGL): the sea, the ship and its flight deck, the helicopter, as the
 * pilot, the landing officer on the deck, a chase camera and an overhead
 * camera see them, with optional overlays (a head-up strip, an airwake
 * slice); frames to PNG and to video through ffmpeg; live rendering beside
 * the flight loop in a thread of its own.
 *
 * Frames. Poses are given in E (NED, docs/conventions.md) as the flight loop
 * publishes them (ship_state_t, heli_state_t); the ship frame S (x bow, y
 * starboard, z down, origin at the landing spot) and the body frame B are
 * placed by them. Images are RGBA, 8 bits per channel, top row first; pixel
 * coordinates are x to the right and y down from the top-left corner, the
 * centre of pixel (i, j) at (i + 0.5, j + 0.5).
 *
 * Determinism: the same scene, state, view and size give the same bytes
 * (llvmpipe is deterministic for a given Mesa build and thread count; the
 * context is created with the rasteriser's thread count fixed, see
 * render_create).
 */
#ifndef DISIM_RENDER_H
#define DISIM_RENDER_H

#include "core.h"
#include "hfm.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct render_ctx render_ctx;

/* Image sides accepted by render_create, in pixels. */
#define RENDER_SIZE_MIN 16
#define RENDER_SIZE_MAX 8192

/* "WIDTHxHEIGHT" (digits only, each RENDER_SIZE_MIN to RENDER_SIZE_MAX)
 * into width and height; < 0 with err saying what was expected. */
int render_size_parse(const char *s, int *width, int *height, core_err *err);
/* An off-screen context of w x h pixels; NULL with err on failure. */
render_ctx *render_create(int width, int height, core_err *err);
void render_destroy(render_ctx *rc);
void render_size(const render_ctx *rc, int *width, int *height);

/* ------------------------------------------------------------ the scene */
/* The sea surface elevation (m, up positive) at n points (x_E, y_E) of E at
 * time t_s: 0, or < 0 to draw a flat sea this frame. The flight's seaway
 * (sim_ship_motion_elevation) is one; NULL in render_scene: a flat sea. */
typedef int (*render_sea_fn)(void *user, double t_s, int n, const double *x_E_m, const double *y_E_m,
                             double *eta_m);

/* The air in S at p_S_m (m/s, relative to the ship), for the airwake
 * overlay: 0, or > 0 outside the field (drawn clear). */
typedef int (*render_air_fn)(void *user, const double p_S_m[3], double v_S_mps[3]);

/* What is drawn (plain data; pointers borrowed for the scene's life). */
typedef struct render_scene {
    const core_ship *ship;         /* required */
    const hfm_geometry *heli;      /* NULL: no helicopter */
    render_sea_fn sea;             /* NULL: a flat sea at the waterline */
    void *sea_user;
    render_air_fn air;             /* NULL: no airwake overlay possible */
    void *air_user;
    double air_ref_mps;            /* the overlay's colour scale: the free-stream speed (> 0) */
    double air_slice_z_S_m;        /* the slice's plane z_S (down; < 0 above the deck); 0: the
                                      hub's height at the first state drawn */
    unsigned overlays;             /* RENDER_OVERLAY_* bits */
    const char *title;             /* the HUD's first line (scenario, run), or NULL */
} render_scene;

#define RENDER_OVERLAY_HUD 1u     /* a head-up strip: attitudes, controls, height over the deck, position */
#define RENDER_OVERLAY_AIRWAKE 2u /* the airwake as a coloured slice through the landing spot */
/* "hud", "airwake", "hud,airwake" (or "none") into RENDER_OVERLAY_* bits;
 * < 0 with err naming the unknown word. */
int render_overlays_parse(const char *list, unsigned *bits, core_err *err);

/* One instant of a run (plain data): what heli_state_t and ship_state_t
 * carry, as the loop publishes them. */
#define RENDER_MAX_LEGS HFM_GEAR_MAX_LEGS
typedef struct render_state {
    double t_s;
    core_pose ship;               /* S's origin (the landing spot) in E and q_ES */
    int have_heli;                /* 0: the ship alone */
    core_pose heli;               /* the CG in E and q_EB */
    double pos_S_m[3];            /* the CG in S */
    double vel_S_mps[3];          /* relative to the ship, in S */
    double roll_rad, pitch_rad, yaw_rad; /* Euler 3-2-1 of B in E */
    double ship_yaw_rad;          /* of S in E */
    double controls_pct[4];       /* collective, longitudinal, lateral, pedal (docs/conventions.md) */
    double rotor_thrust_N;
    int on_deck;
    int n_gear;
    double gear_load_N[RENDER_MAX_LEGS];
    double rotor_azimuth_rad;     /* blade 1's azimuth (drawn blades); the caller keeps it as omega t */
    unsigned flags;               /* sim_status_t FLAG_* bits for the HUD (0: none) */
} render_state;
/* Blade 1's azimuth at t_s for render_state.rotor_azimuth_rad: omega t
 * (rad, within one turn), turning the rotor's way (g->rotor_ccw). */
double render_rotor_azimuth(const hfm_geometry *g, double t_s);

/* ---------------------------------------------------------------- cameras */
typedef enum {
    RENDER_CAM_PILOT = 0,    /* the pilot's eye (the aircraft file's [cockpit] pilot_eye_B_m), looking ahead */
    RENDER_CAM_DECK = 1,     /* the landing officer on deck, on the ship, looking at the helicopter */
    RENDER_CAM_CHASE = 2,    /* behind and above the helicopter, level, along its heading */
    RENDER_CAM_OVERHEAD = 3, /* ship-fixed, straight down on the flight deck */
    RENDER_CAM_COUNT = 4
} render_camera_kind;

/* "pilot", "deck", "chase", "overhead"; < 0 with err listing them. */
int render_camera_parse(const char *name, render_camera_kind *kind, core_err *err);
const char *render_camera_name(render_camera_kind kind);

/* A view: the eye and its axes in E (forward, up: unit and orthogonal),
 * the vertical field of view. Plain data. */
typedef struct render_view {
    double eye_E_m[3];
    double fwd_E[3], up_E[3];
    double fov_y_deg;            /* 1 to 170 */
    double near_m, far_m;        /* clip planes (> 0, far > near) */
} render_view;

/* The view of camera kind at state s of scene sc (the pilot camera needs
 * sc->heli with an eye; the others place themselves from the ship and the
 * state); < 0 with err. */
int render_camera_place(render_camera_kind kind, const render_scene *sc, const render_state *s, render_view *v,
                        core_err *err);

/* A view from eye_E_m looking at target_E_m with E's up (-z_E) as up. */
int render_view_look_at(render_view *v, const double eye_E_m[3], const double target_E_m[3], double fov_y_deg,
                        core_err *err);

/* Where point p_E_m falls in a w x h image of view v: px (x right, y down,
 * pixels) and the depth along the view; 0 if it is in front of the near
 * plane and inside the image, 1 if it is in front but outside, -1 behind.
 * The rasteriser draws with the same projection (the tests rely on it). */
int render_project(const render_view *v, int w, int h, const double p_E_m[3], double px[2], double *depth_m);

/* A point of S (ship) or B (body) into E at state s. */
void render_S_to_E(const render_state *s, const double p_S_m[3], double p_E_m[3]);
void render_B_to_E(const render_state *s, const double p_B_m[3], double p_E_m[3]);

/* ------------------------------------------------------------------ frames */
/* Draw scene sc at state s from view v into rgba (4 * w * h bytes, top row
 * first), overlays included. 0, or < 0 with err (bad view, GL failure). */
int render_frame(render_ctx *rc, const render_scene *sc, const render_state *s, const render_view *v,
                 uint8_t *rgba, core_err *err);

/* The colours of the scene, for tests and legends (RGB 0-255 as drawn
 * under full light: what a surface facing the sun shows is within the
 * lighting's range of these). */
typedef enum {
    RENDER_COLOUR_SKY_ZENITH, RENDER_COLOUR_SKY_HORIZON, RENDER_COLOUR_SEA, RENDER_COLOUR_HULL,
    RENDER_COLOUR_DECK, RENDER_COLOUR_MARKING, RENDER_COLOUR_SPOT, RENDER_COLOUR_LIGHT,
    RENDER_COLOUR_HORIZON_BAR, RENDER_COLOUR_FUSELAGE, RENDER_COLOUR_ROTOR, RENDER_COLOUR_COUNT
} render_colour;
void render_colour_rgb(render_colour c, uint8_t rgb[3]);

/* Write an RGBA image as PNG (cairo), to a temporary file renamed into place. */
int render_write_png(const char *path, int width, int height, const uint8_t *rgba, core_err *err);
/* Read a PNG (cairo) into a new RGBA buffer (free()); golden images. */
int render_read_png(const char *path, int *width, int *height, uint8_t **rgba, core_err *err);

/* The deck view of a scenario without a run (disim render SCENARIO): the
 * ship still and level at the origin, a helicopter marker at heli_S_m (or
 * none), from an eye and target in S. Kept for the still image. */
typedef struct render_camera {
    double eye_S_m[3];
    double target_S_m[3];
    double fov_y_deg;
} render_camera;
int render_deck_view(render_ctx *rc, const core_ship *ship, const render_camera *cam, const double *heli_S_m,
                     uint8_t *rgba, core_err *err);

/* ------------------------------------------------------------------ video */
/* An MP4 (H.264, yuv420p) written by ffmpeg through a pipe: raw RGBA
 * frames in, PATH.tmpPID out, renamed to PATH by render_video_close. No
 * terminal output from ffmpeg (its messages go to a log kept for the
 * error). */
typedef struct render_video render_video;
/* 1 if an ffmpeg that can encode H.264 is on PATH, else 0. */
int render_video_available(void);
render_video *render_video_open(const char *path, int width, int height, double fps, core_err *err);
int render_video_frame(render_video *v, const uint8_t *rgba, core_err *err);
/* Finish: close the pipe, wait for ffmpeg, rename; < 0 with ffmpeg's last
 * message and nothing left at PATH. Frees v either way. */
int render_video_close(render_video *v, core_err *err);
/* Stop ffmpeg and remove the temporary file; frees v. */
void render_video_abort(render_video *v);

/* ------------------------------------------------------------------- live */
/* Live rendering beside a flight loop: the loop hands its latest state to
 * render_live_offer (a copy into a mailbox under a mutex: no GL, no I/O,
 * no allocation in the loop's thread); a thread of its own renders the
 * newest state at most rate_hz times a second of simulation time, and
 * writes frames as PNG (DIR/CAMERA_NNNNNN.png) and/or one MP4 per camera. */
typedef struct render_live_opts {
    const char *dir;           /* where the frames and videos go (created) */
    int width, height;         /* 640 x 480 */
    double rate_hz;            /* frames per second of simulation time (10) */
    unsigned cameras;          /* 1 << render_camera_kind bits (1 << RENDER_CAM_DECK) */
    int png;                   /* 1: PNG frames */
    int video;                 /* 1: an MP4 per camera (needs ffmpeg) */
} render_live_opts;
void render_live_opts_default(render_live_opts *o);
typedef struct render_live render_live;
/* Start the thread; sc (and what it points to) must outlive the live
 * renderer. sc->sea must be safe to call from another thread. Returns
 * once the thread is ready to draw (its context made, a first frame drawn
 * and thrown away); a failure there (the folder, the context, a video) is
 * kept for render_live_destroy. */
render_live *render_live_create(const render_scene *sc, const render_live_opts *o, core_err *err);
/* From the loop: the newest state (copied). Never blocks on the renderer
 * (a try-lock: a state offered while the renderer copies is dropped). */
void render_live_offer(render_live *l, const render_state *s);
/* Whether a state at simulation time t_s is due (a frame's time reached):
 * 1, build it and offer it; 0, it is not (counted as offered and dropped,
 * as render_live_offer would count it), so the loop need not build it.
 * Optional: offering every state gives the same frames. */
int render_live_due(render_live *l, double t_s);
typedef struct render_live_report {
    long frames;               /* frames rendered (all cameras) */
    long offered, dropped;     /* states offered, and those skipped (not due or busy) */
    double render_p50_s, render_p99_s; /* wall time per frame */
} render_live_report;
/* Stop the thread, finish the videos; < 0 with err if a frame or video
 * failed (the first error). Frees l. */
int render_live_destroy(render_live *l, render_live_report *r, core_err *err);

#ifdef __cplusplus
}
#endif
#endif
