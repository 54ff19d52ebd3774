/* scene.h -- a run's scene for the renderer (app/scene.c): shared by
 * `disim render LOG` (cmd_render.c) and `disim fly --render` (cmd_fly.c). */
#ifndef DISIM_APP_SCENE_H
#define DISIM_APP_SCENE_H

#include "cfd.h"
#include "hfm.h"
#include "render.h"
#include "sim.h"

typedef struct app_scene {
    sim_run_scene run;          /* what the run was flown from, its ship, aircraft and seaway (its own) */
    sim_air *air;               /* the airwake overlay's air (NULL: none) */
    struct cfd_field *field;    /* its field (owned) */
    render_scene scene;         /* points into this struct: do not copy an open app_scene */
} app_scene;

/* The scene of run ri (its ship and aircraft files loaded, its seaway
 * rebuilt), with overlays (RENDER_OVERLAY_*). 0, or < 0 with err. */
int app_scene_open(app_scene *s, const sim_run_info *ri, unsigned overlays, const core_log *log, core_err *err);
/* The airwake overlay from the ship-only field flown (taken: freed by
 * app_scene_close), scaled to the run's WOD. 0, or < 0 with err. */
int app_scene_set_field(app_scene *s, struct cfd_field *field, core_err *err);
void app_scene_close(app_scene *s);
/* A state of the flight, or of a log, as the renderer takes it. */
void app_render_state_from_flight(const app_scene *s, const sim_flight_out *o, render_state *rs);
void app_render_state_from_log(const app_scene *s, const sim_log_state *l, render_state *rs);
/* The largest distance (m) between the log's ship and the rebuilt
 * seaway's at 21 of the log's sample times (0 for the same run). */
double app_scene_check_log(const app_scene *s, const sim_log *log);

#endif
