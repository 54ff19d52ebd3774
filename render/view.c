/* view.c -- the off-screen context (OSMesa), PNG in and out, and the still
 * deck view of `disim render SCENARIO`.
 *
 * Determinism: dithering is off (render_frame) and every frame sets the
 * whole GL state it uses, so the same scene, state, view and size give the
 * same bytes. llvmpipe splits the image into tiles rasterised by a pool of
 * threads (LP_NUM_THREADS, the application's to set: the library changes
 * no environment); with this Mesa the bytes do not depend on the thread
 * count: test_render's goldens match to the byte with LP_NUM_THREADS 0, 1,
 * 4 and 8. */
#include "render_priv.h"

#include <cairo.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* One side: digits only (no sign, no blanks), within what render_create
 * takes; strtol's overflow is refused (sscanf's %d let 99999999999
 * through as -1). */
static int size_side(const char *s, const char **end, int *out)
{
    if (*s < '0' || *s > '9')
        return -1;
    char *e;
    errno = 0;
    long v = strtol(s, &e, 10);
    *end = e;
    if (errno == ERANGE || v < RENDER_SIZE_MIN || v > RENDER_SIZE_MAX)
        return -1;
    *out = (int)v;
    return 0;
}

int render_size_parse(const char *s, int *w, int *h, core_err *err)
{
    const char *e;
    int ww, hh;
    if (!s || size_side(s, &e, &ww) || *e != 'x' || size_side(e + 1, &e, &hh) || *e)
        return core_err_set(err, -1, "'%s': expected WIDTHxHEIGHT, e.g. 1280x720, each %d to %d pixels",
                            s ? s : "", RENDER_SIZE_MIN, RENDER_SIZE_MAX);
    *w = ww;
    *h = hh;
    return 0;
}

render_ctx *render_create(int w, int h, core_err *err)
{
    if (w < RENDER_SIZE_MIN || h < RENDER_SIZE_MIN || w > RENDER_SIZE_MAX || h > RENDER_SIZE_MAX) {
        core_err_set(err, -1, "render: image size %dx%d: expected %d to %d pixels a side", w, h,
                     RENDER_SIZE_MIN, RENDER_SIZE_MAX);
        return NULL;
    }
    render_ctx *rc = calloc(1, sizeof *rc);
    if (!rc) {
        core_err_set(err, -1, "render: out of memory");
        return NULL;
    }
    rc->w = w;
    rc->h = h;
    rc->buf = malloc((size_t)4 * w * h);
    /* 24-bit depth, no stencil or accumulation buffers. */
    rc->gl = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, NULL);
    if (!rc->buf || !rc->gl) {
        core_err_set(err, -1, "render: cannot create the OSMesa context");
        render_destroy(rc);
        return NULL;
    }
    return rc;
}

void render_destroy(render_ctx *rc)
{
    if (!rc)
        return;
    render_overlay_free(rc);
    if (rc->gl)
        OSMesaDestroyContext(rc->gl);
    free(rc->buf);
    free(rc);
}

void render_size(const render_ctx *rc, int *width, int *height)
{
    if (width)
        *width = rc ? rc->w : 0;
    if (height)
        *height = rc ? rc->h : 0;
}

int render_deck_view(render_ctx *rc, const core_ship *ship, const render_camera *cam,
                     const double *heli_S_m, uint8_t *rgba, core_err *err)
{
    if (!rc || !ship || !cam || !rgba)
        return core_err_set(err, -1, "render: deck view: expected a context, a ship, a camera and an image");
    if (!(cam->fov_y_deg > 1.0 && cam->fov_y_deg < 170.0))
        return core_err_set(err, -1, "render: fov_y_deg = %g: expected 1 to 170", cam->fov_y_deg);
    /* A camera on its target (or a non-finite one) has no direction. */
    double dist = 0;
    for (int i = 0; i < 3; i++) {
        if (!isfinite(cam->eye_S_m[i]) || !isfinite(cam->target_S_m[i]))
            return core_err_set(err, -1, "render: camera eye_S_m/target_S_m: expected finite values");
        dist += (cam->target_S_m[i] - cam->eye_S_m[i]) * (cam->target_S_m[i] - cam->eye_S_m[i]);
    }
    if (!(sqrt(dist) > 1e-3))
        return core_err_set(err, -1,
                            "render: camera eye_S_m (%g, %g, %g) is on target_S_m: expected them apart",
                            cam->eye_S_m[0], cam->eye_S_m[1], cam->eye_S_m[2]);
    /* The ship still and level at E's origin heading north: S is E. */
    render_scene sc = {.ship = ship};
    render_state st = {.t_s = 0.0};
    st.ship.q_EF = core_quat_identity();
    render_view v;
    if (render_view_look_at(&v, cam->eye_S_m, cam->target_S_m, cam->fov_y_deg, err) < 0 ||
        render_frame_gl(rc, &sc, &st, &v, err) < 0)
        return -1;
    if (heli_S_m) {
        /* The helicopter's position: an orange cross of 2 m arms. */
        glDisable(GL_LIGHTING);
        glDisable(GL_FOG);
        glColor3f(1.0f, 0.55f, 0.0f);
        glLineWidth(3.0f);
        glBegin(GL_LINES);
        for (int a = 0; a < 3; a++) {
            double p0[3] = {heli_S_m[0], heli_S_m[1], heli_S_m[2]}, p1[3];
            memcpy(p1, p0, sizeof p1);
            p0[a] -= 2.0;
            p1[a] += 2.0;
            render_gl_vertex_E(rc, p0);
            render_gl_vertex_E(rc, p1);
        }
        glEnd();
        GLenum ge = glGetError();
        if (ge != GL_NO_ERROR)
            return core_err_set(err, -1, "render: OpenGL error 0x%x", (unsigned)ge);
    }
    render_read_back(rc, rgba);
    return 0;
}

int render_write_png(const char *path, int w, int h, const uint8_t *rgba, core_err *err)
{
    cairo_surface_t *s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
    if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(s);
        return core_err_set(err, -1, "%s: cannot create an image surface", path);
    }
    cairo_surface_flush(s);
    unsigned char *d = cairo_image_surface_get_data(s);
    int stride = cairo_image_surface_get_stride(s);
    for (int y = 0; y < h; y++) {
        uint32_t *o = (uint32_t *)(d + (size_t)y * stride);
        const uint8_t *p = rgba + (size_t)4 * w * y;
        for (int x = 0; x < w; x++)
            o[x] = ((uint32_t)p[4 * x] << 16) | ((uint32_t)p[4 * x + 1] << 8) | p[4 * x + 2];
    }
    cairo_surface_mark_dirty(s);
    /* Sized to the path: a fixed buffer truncated a long one, so the PNG went
     * to another name (an existing file there was overwritten and renamed
     * away) or straight to path itself, with no temporary at all. The
     * process id in the name keeps two renders to one path from writing
     * into each other's temporary. */
    size_t n = strlen(path) + sizeof ".tmp." + 24;
    char *tmp = malloc(n);
    if (!tmp) {
        cairo_surface_destroy(s);
        return core_err_set(err, -1, "%s: out of memory", path);
    }
    snprintf(tmp, n, "%s.tmp.%ld", path, (long)getpid());
    cairo_status_t st = cairo_surface_write_to_png(s, tmp);
    cairo_surface_destroy(s);
    int rc = 0;
    if (st != CAIRO_STATUS_SUCCESS) {
        remove(tmp);
        rc = core_err_set(err, -1, "%s: cannot write PNG: %s", path, cairo_status_to_string(st));
    } else if (rename(tmp, path) != 0) {
        int e = errno;
        remove(tmp);
        rc = core_err_set(err, -1, "%s: cannot rename from %s: %s", path, tmp, strerror(e));
    }
    free(tmp);
    return rc;
}

int render_read_png(const char *path, int *width, int *height, uint8_t **rgba, core_err *err)
{
    *rgba = NULL;
    cairo_surface_t *s = cairo_image_surface_create_from_png(path);
    cairo_status_t st = cairo_surface_status(s);
    if (st != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(s);
        return core_err_set(err, -1, "%s: cannot read PNG: %s", path, cairo_status_to_string(st));
    }
    cairo_format_t fmt = cairo_image_surface_get_format(s);
    int w = cairo_image_surface_get_width(s), h = cairo_image_surface_get_height(s);
    if (fmt != CAIRO_FORMAT_RGB24 && fmt != CAIRO_FORMAT_ARGB32) {
        cairo_surface_destroy(s);
        return core_err_set(err, -1, "%s: PNG of cairo format %d: expected RGB or RGBA, 8 bits a channel", path,
                            (int)fmt);
    }
    uint8_t *o = malloc((size_t)4 * w * h);
    if (!o) {
        cairo_surface_destroy(s);
        return core_err_set(err, -1, "%s: out of memory", path);
    }
    cairo_surface_flush(s);
    const unsigned char *d = cairo_image_surface_get_data(s);
    int stride = cairo_image_surface_get_stride(s);
    for (int y = 0; y < h; y++) {
        const uint32_t *p = (const uint32_t *)(d + (size_t)y * stride);
        for (int x = 0; x < w; x++) {
            uint32_t v = p[x];
            unsigned a = fmt == CAIRO_FORMAT_ARGB32 ? v >> 24 : 255u;
            unsigned c[3] = {(v >> 16) & 255u, (v >> 8) & 255u, v & 255u};
            uint8_t *q = o + (size_t)4 * ((size_t)y * w + x);
            /* cairo keeps premultiplied alpha: undo it. */
            for (int i = 0; i < 3; i++)
                q[i] = (uint8_t)(a == 255u ? c[i] : a == 0u ? 0u : (c[i] * 255u + a / 2u) / a);
            q[3] = (uint8_t)a;
        }
    }
    cairo_surface_destroy(s);
    *width = w;
    *height = h;
    *rgba = o;
    return 0;
}
