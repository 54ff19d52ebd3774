/* view.c -- off-screen deck views with OSMesa.
 *
 * Model: fixed-function OpenGL 1.x with one directional light (a sun from
 * above and ahead) and flat-shaded boxes; perspective by glFrustum and a
 * look-at view built here (no GLU). The ship frame S (z down) maps to GL's
 * y-up world by W = (x_S, -z_S, y_S), a proper rotation (determinant +1), so
 * starboard stays on the right when looking toward the bow. */
#include "render_priv.h"

#include <cairo.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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
    if (rc->gl)
        OSMesaDestroyContext(rc->gl);
    free(rc->buf);
    free(rc);
}

static void to_world(const double s[3], double w[3])
{
    w[0] = s[0];
    w[1] = -s[2];
    w[2] = s[1];
}

static void vertex_S(double x, double y, double z)
{
    double s[3] = {x, y, z}, w[3];
    to_world(s, w);
    glVertex3d(w[0], w[1], w[2]);
}

static void normal_S(double x, double y, double z)
{
    double s[3] = {x, y, z}, w[3];
    to_world(s, w);
    glNormal3d(w[0], w[1], w[2]);
}

/* A quad from four S corners with its outward normal. */
static void quad(const double c[4][3], double nx, double ny, double nz)
{
    normal_S(nx, ny, nz);
    for (int i = 0; i < 4; i++)
        vertex_S(c[i][0], c[i][1], c[i][2]);
}

static void draw_block(const core_ship_block *b)
{
    /* Half-width as a function of x, so a bow taper is a prism. */
    double xt = b->bow_taper_m > 0.0 ? b->x1_m - b->bow_taper_m : b->x1_m;
    double yc = 0.5 * (b->y0_m + b->y1_m), hw = 0.5 * (b->y1_m - b->y0_m);
    double xs[3] = {b->x0_m, xt, b->x1_m};
    double hws[3] = {hw, hw, b->bow_taper_m > 0.0 ? 0.0 : hw};
    double z0 = b->z0_m, z1 = b->z1_m;
    glBegin(GL_QUADS);
    for (int i = 0; i < 2; i++) {
        double xa = xs[i], xb = xs[i + 1], ha = hws[i], hb = hws[i + 1];
        if (xb <= xa)
            continue;
        double top[4][3] = {{xa, yc - ha, z0}, {xb, yc - hb, z0}, {xb, yc + hb, z0}, {xa, yc + ha, z0}};
        quad(top, 0, 0, -1);
        double bot[4][3] = {{xa, yc - ha, z1}, {xa, yc + ha, z1}, {xb, yc + hb, z1}, {xb, yc - hb, z1}};
        quad(bot, 0, 0, 1);
        double dx = xb - xa, dy = ha - hb, n = sqrt(dx * dx + dy * dy);
        double stb[4][3] = {{xa, yc + ha, z0}, {xb, yc + hb, z0}, {xb, yc + hb, z1}, {xa, yc + ha, z1}};
        quad(stb, dy / n, dx / n, 0);
        double prt[4][3] = {{xa, yc - ha, z0}, {xa, yc - ha, z1}, {xb, yc - hb, z1}, {xb, yc - hb, z0}};
        quad(prt, dy / n, -dx / n, 0);
    }
    double aft[4][3] = {{b->x0_m, yc - hw, z0}, {b->x0_m, yc - hw, z1}, {b->x0_m, yc + hw, z1}, {b->x0_m, yc + hw, z0}};
    quad(aft, -1, 0, 0);
    if (b->bow_taper_m <= 0.0) {
        double fwd[4][3] = {{b->x1_m, yc - hw, z0}, {b->x1_m, yc + hw, z0}, {b->x1_m, yc + hw, z1}, {b->x1_m, yc - hw, z1}};
        quad(fwd, 1, 0, 0);
    }
    glEnd();
}

/* Column-major look-at, as gluLookAt builds it. */
static void look_at(const double e[3], const double t[3])
{
    double f[3] = {t[0] - e[0], t[1] - e[1], t[2] - e[2]};
    double nf = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (int i = 0; i < 3; i++)
        f[i] /= nf;
    double up[3] = {0, 1, 0};
    if (fabs(f[1]) > 0.99)
        up[1] = 0, up[2] = 1;
    double s[3] = {f[1] * up[2] - f[2] * up[1], f[2] * up[0] - f[0] * up[2], f[0] * up[1] - f[1] * up[0]};
    double ns = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    for (int i = 0; i < 3; i++)
        s[i] /= ns;
    double u[3] = {s[1] * f[2] - s[2] * f[1], s[2] * f[0] - s[0] * f[2], s[0] * f[1] - s[1] * f[0]};
    double m[16] = {s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0, 0, 0, 0, 1};
    glMultMatrixd(m);
    glTranslated(-e[0], -e[1], -e[2]);
}

int render_deck_view(render_ctx *rc, const core_ship *ship, const render_camera *cam,
                     const double *heli_S_m, uint8_t *rgba, core_err *err)
{
    if (!OSMesaMakeCurrent(rc->gl, rc->buf, GL_UNSIGNED_BYTE, rc->w, rc->h))
        return core_err_set(err, -1, "render: OSMesaMakeCurrent failed");
    if (!(cam->fov_y_deg > 1.0 && cam->fov_y_deg < 170.0))
        return core_err_set(err, -1, "render: fov_y_deg = %g: expected 1 to 170", cam->fov_y_deg);
    /* look_at divides by the eye-to-target distance: a camera on its target
     * (or a non-finite one) gives a NaN view and an image of sky only. */
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
    glViewport(0, 0, rc->w, rc->h);
    glClearColor(0.62f, 0.76f, 0.90f, 1.0f); /* sky */
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    double znear = 0.5, zfar = 5000.0;
    double top = znear * tan(0.5 * cam->fov_y_deg * CORE_DEG_TO_RAD);
    double right = top * rc->w / rc->h;
    glFrustum(-right, right, -top, top, znear, zfar);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    double e[3], t[3];
    to_world(cam->eye_S_m, e);
    to_world(cam->target_S_m, t);
    look_at(e, t);

    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glEnable(GL_COLOR_MATERIAL);
    glEnable(GL_NORMALIZE);
    GLfloat sun[4] = {0.3f, 1.0f, 0.5f, 0.0f}; /* directional, from above */
    GLfloat amb[4] = {0.35f, 0.35f, 0.35f, 1.0f};
    glLightfv(GL_LIGHT0, GL_POSITION, sun);
    glLightModelfv(GL_LIGHT_MODEL_AMBIENT, amb);

    /* Sea: the waterline plane z_S = deck_height. */
    double zw = ship->deck_height_m, L = 2000.0;
    glColor3f(0.10f, 0.25f, 0.42f);
    glBegin(GL_QUADS);
    double sea[4][3] = {{-L, -L, zw}, {-L, L, zw}, {L, L, zw}, {L, -L, zw}};
    quad(sea, 0, 0, -1);
    glEnd();

    glColor3f(0.55f, 0.57f, 0.58f); /* haze grey */
    for (int i = 0; i < ship->nblocks; i++)
        draw_block(&ship->blocks[i]);

    /* Flight deck markings just above the deck: a darker deck, a white circle
     * (the landing spot) and the centre line. */
    glDisable(GL_LIGHTING);
    double zd = -0.02;
    glColor3f(0.30f, 0.31f, 0.32f);
    glBegin(GL_QUADS);
    vertex_S(ship->deck_x0_m, -ship->deck_halfwidth_m, zd);
    vertex_S(ship->deck_x1_m, -ship->deck_halfwidth_m, zd);
    vertex_S(ship->deck_x1_m, ship->deck_halfwidth_m, zd);
    vertex_S(ship->deck_x0_m, ship->deck_halfwidth_m, zd);
    glEnd();
    glColor3f(1.0f, 1.0f, 1.0f);
    glLineWidth(2.0f);
    double r = 0.3 * ship->deck_halfwidth_m;
    glBegin(GL_LINE_LOOP);
    for (int i = 0; i < 48; i++)
        vertex_S(r * cos(2 * CORE_PI * i / 48), r * sin(2 * CORE_PI * i / 48), 2 * zd);
    glEnd();
    glBegin(GL_LINES);
    vertex_S(ship->deck_x0_m, 0, 2 * zd);
    vertex_S(ship->deck_x1_m, 0, 2 * zd);
    glEnd();
    if (heli_S_m) {
        /* The helicopter's position: a cross of 2 m arms. */
        glColor3f(1.0f, 0.55f, 0.0f);
        glLineWidth(3.0f);
        glBegin(GL_LINES);
        for (int a = 0; a < 3; a++) {
            double p0[3] = {heli_S_m[0], heli_S_m[1], heli_S_m[2]}, p1[3];
            memcpy(p1, p0, sizeof p1);
            p0[a] -= 2.0;
            p1[a] += 2.0;
            vertex_S(p0[0], p0[1], p0[2]);
            vertex_S(p1[0], p1[1], p1[2]);
        }
        glEnd();
    }
    glFinish();
    GLenum ge = glGetError();
    if (ge != GL_NO_ERROR)
        return core_err_set(err, -1, "render: OpenGL error 0x%x", (unsigned)ge);
    /* GL's rows run bottom up. */
    size_t row = (size_t)4 * rc->w;
    for (int y = 0; y < rc->h; y++)
        memcpy(rgba + (size_t)y * row, rc->buf + (size_t)(rc->h - 1 - y) * row, row);
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
