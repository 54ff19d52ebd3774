/* otw_priv.h -- the view's parts shared by its files (otw/): the scene,
 * the mailbox between the receive thread and the drawing thread, the two
 * images between the drawing thread and the window. */
#ifndef DISIM_OTW_PRIV_H
#define DISIM_OTW_PRIV_H

#include "otw.h"

#include <lcm/lcm.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>

/* What is drawn: a run's ship, aircraft and seaway (its own seaway object,
 * used by the drawing thread alone). */
typedef struct otw_scene {
    int open;
    sim_run_scene run; /* ship, aircraft, seaway; run.name: ship + aircraft, WOD, sea state */
    render_scene sc;
    char title[256];  /* the strip's first line: the frame rate, the latency, the name */
} otw_scene;
int otw_scene_open(otw_scene *s, const sim_run_info *ri, unsigned overlays, core_err *err);
/* The scene's render_scene points into it: after copying a scene, point
 * the copy's at the copy. */
void otw_scene_moved(otw_scene *s);
void otw_scene_close(otw_scene *s);

/* The newest message of one kind and when it arrived. */
typedef struct otw_part {
    int have;
    int64_t utime;
    double arrival_s;
    int posted;       /* already in a posted state */
} otw_part;

/* Samples for percentiles: every one kept (a frame's latency, its draw time). */
typedef struct otw_samples {
    double *v;
    long n, cap;
} otw_samples;
int otw_samples_add(otw_samples *s, double x);
/* The q-quantile (0..1) of the last `last` samples (all: last <= 0); NAN if none. */
double otw_samples_quantile(const otw_samples *s, long last, double q);
void otw_samples_free(otw_samples *s);

struct otw {
    otw_opts o;
    otw_scene scene;             /* the drawing thread's */
    int scene_ready;             /* under mu: a scene is open */
    pthread_mutex_t mu;
    pthread_cond_t cv;
    /* ---- written by the receive thread, under mu */
    render_state slot;           /* the newest state (no rotor azimuth: the drawing thread's) */
    long slot_seq;               /* +1 per state posted; 0 none */
    double slot_arrival_s;
    render_state next;           /* being assembled from heli_state_t and ship_state_t */
    otw_part heli, ship;
    unsigned status_flags;
    sim_run_info run_info;       /* the loop's, when run_info_seq > 0 */
    long run_info_seq;
    long states, bad_rx;
    char bad_last[256];
    /* ---- the receive thread */
    lcm_t *lc;
    pthread_t rx_th;
    int rx_started;
    atomic_int stop;
    /* ---- the drawing thread and the window, under mu */
    pthread_t draw_th;
    int draw_started;
    uint8_t *img[2];             /* the window shows img[front]; the drawing thread draws the other */
    int front, fresh;            /* fresh: img[front] not yet shown */
    long front_seq, drawn_seq;
    double front_arrival_s, front_draw0_s, front_draw1_s, front_t_s; /* the state's arrival, the drawing's start and end */
    atomic_int camera;
    long redraw;                 /* +1: draw the newest state again (the camera changed) */
    uint32_t ev_frame;           /* the SDL user event of a frame ready */
    char hud_stats[96];          /* the window's figures for the strip */
    int draw_failed;
    core_err draw_err;
    long frames_drawn;
    otw_samples draw_s;
    /* ---- the window's (its thread only) */
    otw_samples latency_s;
    long frames_shown;
    double first_shown_s, last_shown_s;
    FILE *stats;
    char renderer[64];
    int in_pipe[2];              /* the input device: read end for the station, write end for the window */
};

/* The receive thread (rx.c): started by otw_create, stopped by otw_destroy. */
int otw_rx_start(otw *w, core_err *err);
void otw_rx_stop(otw *w);
/* The drawing thread (draw.c), started by otw_run once SDL is up. */
void *otw_draw_main(void *arg);

#endif
