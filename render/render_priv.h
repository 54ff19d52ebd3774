/* render_priv.h -- what render/'s files share and nothing outside sees.
 *
 * The GL world. Each frame is drawn in a local copy of E with its origin
 * at origin_E_m (the landing spot at the frame's time: coordinates stay
 * small, so single-precision vertices keep millimetres far from E's
 * origin), mapped to GL's y-up axes by
 *     W = (x_E - o_x, -(z_E - o_z), y_E - o_y)
 * (north, up, east: a proper rotation, determinant +1). render_gl_vertex_E
 * and render_gl_normal_E do that mapping; every file draws through them.
 */
#ifndef DISIM_RENDER_PRIV_H
#define DISIM_RENDER_PRIV_H

#include "render.h"

#include <GL/gl.h>
#include <GL/osmesa.h>

struct render_ctx {
    OSMesaContext gl;
    int w, h;
    uint8_t *buf;          /* GL's image, bottom row first */
    double origin_E_m[3];  /* the GL world's origin this frame */
    /* the airwake overlay's slice, sampled once per scene (overlay.c) */
    const void *slice_key; /* the render_scene.air_user it was sampled from (NULL: none) */
    double slice_ref_mps;
    int slice_nx, slice_ny;
    uint8_t *slice_rgba;   /* slice_nx * slice_ny RGBA texels */
    double slice_x0_m, slice_x1_m, slice_y0_m, slice_y1_m, slice_z_m; /* its plane in S */
};

static inline void render_gl_vertex_E(const render_ctx *rc, const double p[3])
{
    glVertex3d(p[0] - rc->origin_E_m[0], -(p[2] - rc->origin_E_m[2]), p[1] - rc->origin_E_m[1]);
}
static inline void render_gl_normal_E(const double n[3]) { glNormal3d(n[0], -n[2], n[1]); }

/* overlay.c: the airwake slice, drawn in GL after the opaque scene (blended,
 * depth-tested); 0 or < 0 with err. */
int render_overlay_airwake(render_ctx *rc, const render_scene *sc, const render_state *s, core_err *err);
/* overlay.c: the head-up strip, drawn with cairo onto the finished image
 * (top row first); 0 or < 0 with err. It draws the strip when sc->overlays
 * has RENDER_OVERLAY_HUD and the airwake's colour legend when it has
 * RENDER_OVERLAY_AIRWAKE (nothing when neither): call it for every frame. */
int render_overlay_hud(const render_scene *sc, const render_state *s, const render_view *v, int w, int h,
                       uint8_t *rgba, core_err *err);
/* overlay.c: frees the slice cache (render_destroy calls it). */
void render_overlay_free(render_ctx *rc);
/* overlay.c, for the tests: the slice's colour map (speed over air_ref_mps:
 * blue at 1 - RENDER_AIR_SPAN, grey at 1, red at 1 + RENDER_AIR_SPAN); the
 * sampling of the slice into rc->slice_* (no GL; cached per scene, as
 * render_overlay_airwake does it); the heights of the HUD's top and
 * bottom bands, the only rows render_overlay_hud changes. */
#define RENDER_AIR_SPAN 0.5
void render_overlay_air_colour(double speed_ratio, uint8_t rgb[3]);
int render_overlay_air_sample(render_ctx *rc, const render_scene *sc, const render_state *s, core_err *err);
void render_overlay_hud_bands(int w, int h, int *top_px, int *bottom_px);
/* overlay.c: the HUD's height over the deck (m): the lowest wheel's bottom
 * above the deck plane (z_S = 0) when sc->heli has gear, else the CG's. */
double render_overlay_deck_height(const render_scene *sc, const render_state *s);

/* camera.c: 0, or < 0 with err naming what is wrong with view v. */
int render_view_check(const render_view *v, core_err *err);
/* camera.c: the GL projection and model-view matrices (column-major) of
 * view v in a w x h image, for the GL world with its origin at origin_E_m;
 * render_frame and render_project both use them (one projection). */
void render_gl_matrices(const render_view *v, int w, int h, const double origin_E_m[3], double proj[16],
                        double mv[16]);
/* scene.c: render_frame's drawing without the read-back and the HUD (the GL
 * image stays in rc->buf, bottom row first); view.c adds its marker. */
int render_frame_gl(render_ctx *rc, const render_scene *sc, const render_state *s, const render_view *v,
                    core_err *err);
/* scene.c: rc->buf (bottom row first) into rgba (top row first). */
void render_read_back(const render_ctx *rc, uint8_t *rgba);

#endif
