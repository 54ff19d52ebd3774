/*
 * render.h -- off-screen views of the ship and the deck (OSMesa, software
 * OpenGL), for deck views and video frames of recorded runs.
 *
 * The scene is drawn in the ship frame S (x bow, y starboard, z down, origin
 * at the landing spot); the camera is given in S too. Images are RGBA, 8 bits
 * per channel, top row first.
 */
#ifndef DISIM_RENDER_H
#define DISIM_RENDER_H

#include "core.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct render_ctx render_ctx;

typedef struct render_camera {
    double eye_S_m[3];    /* camera position in S */
    double target_S_m[3]; /* point looked at, in S */
    double fov_y_deg;     /* vertical field of view */
} render_camera;

/* Image sides accepted by render_create, in pixels. */
#define RENDER_SIZE_MIN 16
#define RENDER_SIZE_MAX 8192

/* An off-screen context of w x h pixels; NULL with err on failure. */
render_ctx *render_create(int width, int height, core_err *err);
void render_destroy(render_ctx *rc);

/* Draw the sea, the ship's blocks (flight deck marked) and, if heli_S_m is
 * not NULL, a marker at the helicopter's position; the image goes to rgba
 * (4 * w * h bytes, top row first). */
int render_deck_view(render_ctx *rc, const core_ship *ship, const render_camera *cam,
                     const double *heli_S_m, uint8_t *rgba, core_err *err);

/* Write an RGBA image as PNG (cairo), to a temporary file renamed into place. */
int render_write_png(const char *path, int width, int height, const uint8_t *rgba, core_err *err);

#ifdef __cplusplus
}
#endif
#endif
