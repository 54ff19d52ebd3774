/* overlay.c -- the overlays: a head-up strip (cairo, on the finished image)
 * and the airwake as a coloured slice through the landing spot's air (GL).
 *
 * The head-up strip is what a test pilot reads on a deck landing: along the
 * bottom the attitudes (RHDG: the heading relative to the ship's), the height of the
 * lowest wheel over the deck plane, the position from the spot and the
 * velocity relative to the deck in S, and the four controls as bars; along
 * the top the title, the time and the state (ON DECK and the sim_status_t
 * SLIDE / TIP OVER / CRASH flags). Text is white labels and green values
 * on a semi-transparent dark band; the font scales with the image
 * (legible from 640 x 480 up). Cairo draws on a copy of the bands only
 * (CAIRO_FORMAT_RGB24, a native-endian 32-bit word 0x00RRGGBB, converted
 * from and back to the image's R, G, B, A bytes), so the rows between the
 * bands are never touched and the image's alpha is kept.
 *
 * The airwake slice is the plane z_S = sc->air_slice_z_S_m (or the rotor
 * hub's height at the first state drawn) over x_S from the deck's aft end
 * - 40 m to its forward end + 10 m and y_S within +-(beam + 20 m), sampled
 * once per scene through sc->air every 0.5 m (coarser where a side would
 * pass 512 texels). Colour: the speed relative to the ship over
 * sc->air_ref_mps, r = |v| / V_ref, on the cool-warm diverging map of
 * Moreland (2009, "Diverging color maps for scientific visualization",
 * ISVC, table of the 33-point map) from r = 1 - RENDER_AIR_SPAN (blue, a
 * deficit) through r = 1 (grey) to r = 1 + RENDER_AIR_SPAN (red, an
 * excess), alpha 0.5; texels outside the field are clear. It is drawn as
 * one textured quad (GL_NEAREST: each texel is one sample), blended,
 * depth-tested without depth writes, after the opaque scene. */
#include "render_priv.h"

#include <cairo.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* sim_status_t's flag bits (lcm_types/sim_status_t.lcm). */
#define FLAG_ON_DECK 64u
#define FLAG_SLIDE 128u
#define FLAG_TIP_OVER 256u
#define FLAG_CRASH 512u

#define SLICE_STEP_M 0.5
#define SLICE_MAX_TEXELS 512
#define SLICE_ALPHA 128

/* ------------------------------------------------------------ parsing */
int render_overlays_parse(const char *list, unsigned *bits, core_err *err)
{
    if (!list || !bits)
        return core_err_set(err, -1, "render: overlays: expected a list such as \"hud,airwake\" or \"none\"");
    unsigned b = 0;
    int words = 0, none = 0;
    const char *p = list;
    for (;;) {
        const char *q = strchr(p, ',');
        size_t n = q ? (size_t)(q - p) : strlen(p);
        while (n > 0 && (*p == ' ' || *p == '\t'))
            p++, n--;
        while (n > 0 && (p[n - 1] == ' ' || p[n - 1] == '\t'))
            n--;
        if (n == 3 && strncmp(p, "hud", 3) == 0)
            b |= RENDER_OVERLAY_HUD;
        else if (n == 7 && strncmp(p, "airwake", 7) == 0)
            b |= RENDER_OVERLAY_AIRWAKE;
        else if (n == 4 && strncmp(p, "none", 4) == 0)
            none = 1;
        else if (n == 0)
            return core_err_set(err, -1, "render: overlays \"%s\": an empty item: expected hud, airwake or none",
                                list);
        else
            return core_err_set(err, -1, "render: overlays \"%s\": unknown overlay \"%.*s\": expected hud, "
                                "airwake or none", list, (int)n, p);
        words++;
        if (!q)
            break;
        p = q + 1;
    }
    if (none && words > 1)
        return core_err_set(err, -1, "render: overlays \"%s\": \"none\" goes alone", list);
    *bits = b;
    return 0;
}

/* ------------------------------------------------------ the colour map */
/* Moreland's cool-warm map, 33 points from 0 (blue) to 1 (red). */
static const uint8_t coolwarm[33][3] = {
    {59, 76, 192},   {68, 90, 204},   {77, 104, 215},  {87, 117, 225},  {98, 130, 234},  {108, 142, 241},
    {119, 154, 247}, {130, 165, 251}, {141, 176, 254}, {152, 185, 255}, {163, 194, 255}, {174, 201, 253},
    {184, 208, 249}, {194, 213, 244}, {204, 217, 238}, {213, 219, 230}, {221, 221, 221}, {229, 216, 209},
    {236, 211, 197}, {241, 204, 185}, {245, 196, 173}, {247, 187, 160}, {247, 177, 148}, {247, 166, 135},
    {244, 154, 123}, {241, 141, 111}, {236, 127, 99},  {229, 112, 88},  {222, 96, 77},   {213, 80, 66},
    {203, 62, 56},   {192, 40, 47},   {180, 4, 38}};

void render_overlay_air_colour(double speed_ratio, uint8_t rgb[3])
{
    double t = 0.5 + 0.5 * (speed_ratio - 1.0) / RENDER_AIR_SPAN;
    if (!(t > 0.0)) /* NaN too */
        t = 0.0;
    if (t > 1.0)
        t = 1.0;
    double f = t * 32.0;
    int i = (int)f;
    if (i > 31)
        i = 31;
    double a = f - i;
    for (int c = 0; c < 3; c++)
        rgb[c] = (uint8_t)lround((1.0 - a) * coolwarm[i][c] + a * coolwarm[i + 1][c]);
}

/* ------------------------------------------------------ the slice cache */
void render_overlay_free(render_ctx *rc)
{
    if (!rc)
        return;
    free(rc->slice_rgba);
    rc->slice_rgba = NULL;
    rc->slice_key = NULL;
    rc->slice_nx = rc->slice_ny = 0;
}

/* The slice's plane: given, or the hub's height in S at state s. */
static double slice_z(const render_scene *sc, const render_state *s)
{
    if (sc->air_slice_z_S_m != 0.0)
        return sc->air_slice_z_S_m;
    if (s && s->have_heli) {
        if (sc->heli) {
            double hub_E[3], hub_S[3];
            render_B_to_E(s, sc->heli->hub_B_m, hub_E);
            core_vec3 p = core_pose_point_from_E(&s->ship, core_vec3_make(hub_E[0], hub_E[1], hub_E[2]));
            hub_S[2] = p.z;
            return hub_S[2];
        }
        return s->pos_S_m[2];
    }
    return -5.0; /* no helicopter: 5 m above the deck */
}

int render_overlay_air_sample(render_ctx *rc, const render_scene *sc, const render_state *s, core_err *err)
{
    if (!sc || !sc->ship)
        return core_err_set(err, -1, "render: airwake overlay: no scene or no ship");
    if (!sc->air)
        return core_err_set(err, -1, "render: airwake overlay: the scene has no air field (render_scene.air)");
    if (!(sc->air_ref_mps > 0.0) || !isfinite(sc->air_ref_mps))
        return core_err_set(err, -1, "render: airwake overlay: air_ref_mps = %g: expected a speed > 0",
                            sc->air_ref_mps);
    if (rc->slice_rgba && rc->slice_key == sc->air_user && rc->slice_ref_mps == sc->air_ref_mps)
        return 0;
    render_overlay_free(rc);
    const core_ship *sh = sc->ship;
    double x0 = sh->deck_x0_m - 40.0, x1 = sh->deck_x1_m + 10.0;
    double y1 = sh->beam_m + 20.0, y0 = -y1;
    double z = slice_z(sc, s);
    if (!isfinite(z) || !(x1 > x0))
        return core_err_set(err, -1, "render: airwake overlay: the slice's plane (z_S = %g m, x_S %g to %g m) "
                            "is not usable", z, x0, x1);
    int nx = (int)ceil((x1 - x0) / SLICE_STEP_M), ny = (int)ceil((y1 - y0) / SLICE_STEP_M);
    if (nx > SLICE_MAX_TEXELS)
        nx = SLICE_MAX_TEXELS;
    if (ny > SLICE_MAX_TEXELS)
        ny = SLICE_MAX_TEXELS;
    uint8_t *t = malloc((size_t)4 * nx * ny);
    if (!t)
        return core_err_set(err, -1, "render: airwake overlay: out of memory");
    double dx = (x1 - x0) / nx, dy = (y1 - y0) / ny;
    for (int j = 0; j < ny; j++) {
        for (int i = 0; i < nx; i++) {
            double p[3] = {x0 + (i + 0.5) * dx, y0 + (j + 0.5) * dy, z}, v[3] = {0, 0, 0};
            uint8_t *o = t + 4 * ((size_t)j * nx + i);
            int r = sc->air(sc->air_user, p, v);
            if (r < 0) {
                free(t);
                return core_err_set(err, -1, "render: airwake overlay: the air field failed at S (%g, %g, %g) m",
                                    p[0], p[1], p[2]);
            }
            double sp = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            if (r > 0 || !isfinite(sp)) {
                o[0] = o[1] = o[2] = o[3] = 0;
                continue;
            }
            render_overlay_air_colour(sp / sc->air_ref_mps, o);
            o[3] = SLICE_ALPHA;
        }
    }
    rc->slice_rgba = t;
    rc->slice_key = sc->air_user;
    rc->slice_ref_mps = sc->air_ref_mps;
    rc->slice_nx = nx;
    rc->slice_ny = ny;
    rc->slice_x0_m = x0;
    rc->slice_x1_m = x1;
    rc->slice_y0_m = y0;
    rc->slice_y1_m = y1;
    rc->slice_z_m = z;
    return 0;
}

int render_overlay_airwake(render_ctx *rc, const render_scene *sc, const render_state *s, core_err *err)
{
    if (!(sc->overlays & RENDER_OVERLAY_AIRWAKE))
        return 0;
    int r = render_overlay_air_sample(rc, sc, s, err);
    if (r != 0)
        return r;
    while (glGetError() != GL_NO_ERROR) /* not ours */
        ;
    glPushAttrib(GL_ENABLE_BIT | GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_TEXTURE_BIT | GL_LIGHTING_BIT |
                 GL_CURRENT_BIT | GL_POLYGON_BIT | GL_PIXEL_MODE_BIT);
    glPushClientAttrib(GL_CLIENT_PIXEL_STORE_BIT);
    GLuint tex = 0;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, rc->slice_nx, rc->slice_ny, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 rc->slice_rgba);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    glEnable(GL_TEXTURE_2D);
    glDisable(GL_LIGHTING);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_FALSE);
    const double xs[4] = {rc->slice_x0_m, rc->slice_x1_m, rc->slice_x1_m, rc->slice_x0_m};
    const double ys[4] = {rc->slice_y0_m, rc->slice_y0_m, rc->slice_y1_m, rc->slice_y1_m};
    const double ts[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    glBegin(GL_QUADS);
    for (int k = 0; k < 4; k++) {
        double pS[3] = {xs[k], ys[k], rc->slice_z_m}, pE[3];
        render_S_to_E(s, pS, pE);
        glTexCoord2d(ts[k][0], ts[k][1]);
        render_gl_vertex_E(rc, pE);
    }
    glEnd();
    glDeleteTextures(1, &tex);
    glPopClientAttrib();
    glPopAttrib();
    GLenum e = glGetError();
    if (e != GL_NO_ERROR)
        return core_err_set(err, -1, "render: airwake overlay: GL error 0x%04x", (unsigned)e);
    return 0;
}

/* ------------------------------------------------------- the HUD bands */
/* A band of image rows [y0, y0 + n) copied into a cairo RGB24 surface. */
typedef struct band {
    cairo_surface_t *sf;
    cairo_t *cr;
    int y0, n;
} band;

static int band_open(band *b, const uint8_t *rgba, int w, int h, int y0, int n)
{
    memset(b, 0, sizeof *b);
    if (y0 < 0)
        n += y0, y0 = 0;
    if (y0 + n > h)
        n = h - y0;
    if (n <= 0)
        return 1;
    b->y0 = y0;
    b->n = n;
    b->sf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, n);
    if (cairo_surface_status(b->sf) != CAIRO_STATUS_SUCCESS)
        return -1;
    unsigned char *d = cairo_image_surface_get_data(b->sf);
    int stride = cairo_image_surface_get_stride(b->sf);
    for (int j = 0; j < n; j++) {
        const uint8_t *s = rgba + 4 * ((size_t)(y0 + j) * w);
        uint32_t *o = (uint32_t *)(void *)(d + (size_t)j * stride);
        for (int i = 0; i < w; i++, s += 4)
            o[i] = ((uint32_t)s[0] << 16) | ((uint32_t)s[1] << 8) | s[2];
    }
    cairo_surface_mark_dirty(b->sf);
    b->cr = cairo_create(b->sf);
    if (cairo_status(b->cr) != CAIRO_STATUS_SUCCESS)
        return -1;
    cairo_translate(b->cr, 0, -y0); /* draw in image coordinates */
    return 0;
}

/* Copy the band back (alpha kept) and free it; 0, or -1 if cairo failed. */
static int band_close(band *b, uint8_t *rgba, int w)
{
    int rc = 0;
    if (b->cr) {
        if (cairo_status(b->cr) != CAIRO_STATUS_SUCCESS)
            rc = -1;
        cairo_destroy(b->cr);
    }
    if (b->sf) {
        cairo_surface_flush(b->sf);
        if (rc == 0 && cairo_surface_status(b->sf) == CAIRO_STATUS_SUCCESS) {
            const unsigned char *d = cairo_image_surface_get_data(b->sf);
            int stride = cairo_image_surface_get_stride(b->sf);
            for (int j = 0; j < b->n; j++) {
                uint8_t *o = rgba + 4 * ((size_t)(b->y0 + j) * w);
                const uint32_t *s = (const uint32_t *)(const void *)(d + (size_t)j * stride);
                for (int i = 0; i < w; i++, o += 4) {
                    o[0] = (uint8_t)(s[i] >> 16);
                    o[1] = (uint8_t)(s[i] >> 8);
                    o[2] = (uint8_t)s[i];
                }
            }
        } else {
            rc = -1;
        }
        cairo_surface_destroy(b->sf);
    }
    memset(b, 0, sizeof *b);
    return rc;
}

/* The HUD's measures, in pixels, from the image's size. */
typedef struct hud_geom {
    double fs, lh, pad, cw;  /* font size, line height, padding, a character's advance */
    int top_h, bot_h;        /* the bands' heights */
} hud_geom;

static void hud_geom_make(int w, int h, hud_geom *g)
{
    double fs = fmin(h / 36.0, w / 54.0);
    if (fs < 7.0)
        fs = 7.0;
    g->fs = fs;
    g->lh = 1.3 * fs;
    g->pad = 0.4 * fs;
    g->cw = 0.602 * fs; /* DejaVu Sans Mono's advance; layout only */
    g->top_h = (int)ceil(g->lh + 2 * g->pad);
    g->bot_h = (int)ceil(3 * g->lh + 2 * g->pad);
}

static const double WHITE[3] = {1, 1, 1}, GREEN[3] = {0.45, 1.0, 0.45}, AMBER[3] = {1.0, 0.75, 0.2},
                    RED[3] = {1.0, 0.3, 0.25};

static void text_at(cairo_t *cr, double x, double y, const double c[3], const char *s)
{
    cairo_set_source_rgb(cr, c[0], c[1], c[2]);
    cairo_move_to(cr, x, y);
    cairo_show_text(cr, s);
}

static double text_w(cairo_t *cr, const char *s)
{
    cairo_text_extents_t e;
    cairo_text_extents(cr, s, &e);
    return e.x_advance;
}

/* A label in white then its value in green, on baseline y. */
static void field(cairo_t *cr, double x, double y, const char *label, const char *value)
{
    text_at(cr, x, y, WHITE, label);
    text_at(cr, x + text_w(cr, label), y, GREEN, value);
}

/* The height over the deck plane: the lowest wheel's bottom with gear, else
 * the CG's. */
double render_overlay_deck_height(const render_scene *sc, const render_state *s)
{
    if (sc->heli && sc->heli->gear.nlegs > 0) {
        double lowest = HUGE_VAL;
        for (int k = 0; k < sc->heli->gear.nlegs && k < HFM_GEAR_MAX_LEGS; k++) {
            const hfm_gear_leg *leg = &sc->heli->gear.leg[k];
            double pE[3];
            render_B_to_E(s, leg->pos_B_m, pE);
            core_vec3 pS = core_pose_point_from_E(&s->ship, core_vec3_make(pE[0], pE[1], pE[2]));
            double hgt = -pS.z - leg->tyre_radius_m;
            if (hgt < lowest)
                lowest = hgt;
        }
        return lowest;
    }
    return -s->pos_S_m[2];
}

/* A control bar: outline, fill from the left to pct, a tick at 50 %. */
static void control_bar(cairo_t *cr, const hud_geom *g, double x, double y, double bw, const char *name,
                        double pct)
{
    char txt[32];
    snprintf(txt, sizeof txt, "%3.0f%%", pct);
    text_at(cr, x, y, WHITE, name);
    double bx = x + 4 * g->cw, bh = 0.62 * g->fs, by = y - bh;
    double frac = pct / 100.0;
    if (!(frac > 0.0))
        frac = 0.0;
    if (frac > 1.0)
        frac = 1.0;
    const double *c = (pct > 85.0 || pct < 15.0) ? AMBER : GREEN;
    cairo_set_source_rgba(cr, c[0], c[1], c[2], 0.85);
    cairo_rectangle(cr, bx, by, bw * frac, bh);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_set_line_width(cr, fmax(1.0, g->fs / 12.0));
    cairo_rectangle(cr, bx, by, bw, bh);
    cairo_stroke(cr);
    cairo_move_to(cr, bx + 0.5 * bw, by - 0.2 * bh);
    cairo_line_to(cr, bx + 0.5 * bw, by + 1.2 * bh);
    cairo_stroke(cr);
    text_at(cr, bx + bw + 0.5 * g->cw, y, GREEN, txt);
}

static void draw_bottom(cairo_t *cr, const hud_geom *g, const render_scene *sc, const render_state *s, int w,
                        int h)
{
    double y0 = h - g->bot_h;
    cairo_set_source_rgba(cr, 0.0, 0.0, 0.0, 0.55);
    cairo_rectangle(cr, 0, y0, w, g->bot_h);
    cairo_fill(cr);
    double base[3];
    for (int k = 0; k < 3; k++)
        base[k] = y0 + g->pad + (k + 0.78) * g->lh;
    double x = g->pad;
    char v[64];
    if (!s->have_heli) {
        text_at(cr, x, base[1], WHITE, "SHIP ONLY: no helicopter in this state");
        return;
    }
    const double r2d = 180.0 / M_PI;
    snprintf(v, sizeof v, "%+6.1f\xc2\xb0", s->roll_rad * r2d);
    field(cr, x, base[0], "ROLL  ", v);
    snprintf(v, sizeof v, "%+6.1f\xc2\xb0", s->pitch_rad * r2d);
    field(cr, x, base[1], "PITCH ", v);
    snprintf(v, sizeof v, "%+6.1f\xc2\xb0", core_wrap_pi(s->yaw_rad - s->ship_yaw_rad) * r2d);
    field(cr, x, base[2], "RHDG  ", v);
    x += 14 * g->cw;
    snprintf(v, sizeof v, "%6.2f m", render_overlay_deck_height(sc, s));
    field(cr, x, base[0], "HGT ", v);
    snprintf(v, sizeof v, "%+6.2f m", s->pos_S_m[0]);
    field(cr, x, base[1], "FWD ", v);
    snprintf(v, sizeof v, "%+6.2f m", s->pos_S_m[1]);
    field(cr, x, base[2], "STB ", v);
    x += 13.5 * g->cw;
    snprintf(v, sizeof v, "%+5.1f m/s", s->vel_S_mps[0]);
    field(cr, x, base[0], "VX ", v);
    snprintf(v, sizeof v, "%+5.1f m/s", s->vel_S_mps[1]);
    field(cr, x, base[1], "VY ", v);
    snprintf(v, sizeof v, "%+5.1f m/s", s->vel_S_mps[2]);
    field(cr, x, base[2], "VZ ", v);
    x += 14 * g->cw;
    /* The controls fill what is left: two columns of two bars. */
    static const char *names[4] = {"COL", "LON", "LAT", "PED"};
    double colw = (w - g->pad - x) / 2.0;
    double bw = colw - 9.5 * g->cw;
    if (bw < 2 * g->cw) { /* narrow images: one column of four, smaller */
        bw = w - g->pad - x - 9.5 * g->cw;
        colw = 0;
    }
    if (bw < g->cw)
        bw = g->cw;
    for (int k = 0; k < 4; k++) {
        double cx = colw > 0 ? x + (k / 2) * colw : x;
        double cy = colw > 0 ? base[k % 2] : y0 + g->pad + (k + 0.85) * (3 * g->lh / 4);
        control_bar(cr, g, cx, cy, bw, names[k], s->controls_pct[k]);
    }
    if (colw > 0) {
        snprintf(v, sizeof v, "%5.1f kN", s->rotor_thrust_N / 1000.0);
        field(cr, x, base[2], "THRUST ", v);
    }
}

/* The airwake legend: the colour bar from 1 - span to 1 + span of V_ref,
 * ending at x_right on baseline y (the tick in the middle is V_ref);
 * returns where it starts. */
static double draw_legend(cairo_t *cr, const hud_geom *g, const render_scene *sc, double x_right, double y,
                          int boxed)
{
    char l0[32], l1[32];
    const char *title = "AIR |V| ";
    snprintf(l0, sizeof l0, "%.1f ", (1.0 - RENDER_AIR_SPAN) * sc->air_ref_mps);
    snprintf(l1, sizeof l1, " %.1f m/s", (1.0 + RENDER_AIR_SPAN) * sc->air_ref_mps);
    double bw = 12 * g->cw, bh = 0.7 * g->fs;
    double w1 = text_w(cr, l1), w0 = text_w(cr, l0), wt = text_w(cr, title);
    double bx = x_right - w1 - bw, x0 = bx - w0 - wt;
    if (boxed) {
        cairo_set_source_rgba(cr, 0.0, 0.0, 0.0, 0.55);
        cairo_rectangle(cr, x0 - g->pad, y - 0.78 * g->lh - g->pad, x_right - x0 + 2 * g->pad, g->lh + 2 * g->pad);
        cairo_fill(cr);
    }
    text_at(cr, x0, y, WHITE, title);
    text_at(cr, bx - w0, y, GREEN, l0);
    cairo_pattern_t *grad = cairo_pattern_create_linear(bx, 0, bx + bw, 0);
    for (int k = 0; k < 33; k++)
        cairo_pattern_add_color_stop_rgb(grad, k / 32.0, coolwarm[k][0] / 255.0, coolwarm[k][1] / 255.0,
                                         coolwarm[k][2] / 255.0);
    cairo_set_source(cr, grad);
    cairo_rectangle(cr, bx, y - bh, bw, bh);
    cairo_fill(cr);
    cairo_pattern_destroy(grad);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_set_line_width(cr, fmax(1.0, g->fs / 12.0));
    cairo_move_to(cr, bx + 0.5 * bw, y - 1.25 * bh);
    cairo_line_to(cr, bx + 0.5 * bw, y + 0.25 * bh);
    cairo_stroke(cr);
    text_at(cr, bx + bw, y, GREEN, l1);
    return x0;
}

static void draw_top(cairo_t *cr, const hud_geom *g, const render_scene *sc, const render_state *s, int w,
                     int legend)
{
    cairo_set_source_rgba(cr, 0.0, 0.0, 0.0, 0.55);
    cairo_rectangle(cr, 0, 0, w, g->top_h);
    cairo_fill(cr);
    double y = g->pad + 0.78 * g->lh, x = g->pad;
    char t[48];
    snprintf(t, sizeof t, "%.2f s   ", s->t_s);
    field(cr, x, y, "T ", t);
    x += text_w(cr, "T ") + text_w(cr, t);
    /* The state on the right; the title gets what is left between. */
    const char *word[4];
    const double *col[4];
    int nw = 0;
    if (s->have_heli && (s->on_deck || (s->flags & FLAG_ON_DECK)))
        word[nw] = "ON DECK", col[nw++] = GREEN;
    if (s->flags & FLAG_SLIDE)
        word[nw] = "SLIDE", col[nw++] = AMBER;
    if (s->flags & FLAG_TIP_OVER)
        word[nw] = "TIP OVER", col[nw++] = RED;
    if (s->flags & FLAG_CRASH)
        word[nw] = "CRASH", col[nw++] = RED;
    if (s->have_heli && nw == 0)
        word[nw] = "AIRBORNE", col[nw++] = WHITE;
    double xr = w - g->pad;
    for (int k = nw - 1; k >= 0; k--) {
        xr -= text_w(cr, word[k]);
        text_at(cr, xr, y, col[k], word[k]);
        xr -= 1.5 * g->cw;
    }
    if (legend)
        xr = draw_legend(cr, g, sc, xr - g->cw, y, 0) - 1.5 * g->cw;
    if (sc->title && sc->title[0] && xr - x > 4 * g->cw) {
        cairo_save(cr);
        cairo_rectangle(cr, x, 0, xr - x - g->cw, g->top_h);
        cairo_clip(cr);
        text_at(cr, x, y, GREEN, sc->title);
        cairo_restore(cr);
    }
}

int render_overlay_hud(const render_scene *sc, const render_state *s, const render_view *v, int w, int h,
                       uint8_t *rgba, core_err *err)
{
    (void)v;
    if (!sc || !s || !rgba)
        return core_err_set(err, -1, "render: HUD: no scene, state or image");
    int hud = (sc->overlays & RENDER_OVERLAY_HUD) != 0;
    int legend = (sc->overlays & RENDER_OVERLAY_AIRWAKE) && sc->air && sc->air_ref_mps > 0.0;
    if (!hud && !legend)
        return 0;
    if (w < RENDER_SIZE_MIN || h < RENDER_SIZE_MIN || w > RENDER_SIZE_MAX || h > RENDER_SIZE_MAX)
        return core_err_set(err, -1, "render: HUD: image size %dx%d: expected %d to %d pixels a side", w, h,
                            RENDER_SIZE_MIN, RENDER_SIZE_MAX);
    hud_geom g;
    hud_geom_make(w, h, &g);
    int rc = 0;
    band top, bot;
    /* The top band (with the legend), then the bottom strip; on an image
     * too short for both, the top band yields. */
    int bot_ok = hud && h >= g.bot_h;
    int top_ok = h - (bot_ok ? g.bot_h : 0) >= g.top_h;
    if (top_ok) {
        int r = band_open(&top, rgba, w, h, 0, g.top_h);
        if (r < 0) {
            band_close(&top, rgba, w);
            return core_err_set(err, -1, "render: HUD: cairo could not make a %dx%d surface", w, g.top_h);
        }
        cairo_select_font_face(top.cr, "monospace", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
        cairo_set_font_size(top.cr, g.fs);
        if (hud)
            draw_top(top.cr, &g, sc, s, w, legend);
        else
            draw_legend(top.cr, &g, sc, w - g.pad, g.pad + 0.78 * g.lh, 1);
        if (band_close(&top, rgba, w) != 0)
            rc = core_err_set(err, -1, "render: HUD: cairo failed drawing the top band");
    }
    if (bot_ok && rc == 0) {
        int r = band_open(&bot, rgba, w, h, h - g.bot_h, g.bot_h);
        if (r < 0) {
            band_close(&bot, rgba, w);
            return core_err_set(err, -1, "render: HUD: cairo could not make a %dx%d surface", w, g.bot_h);
        }
        cairo_select_font_face(bot.cr, "monospace", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
        cairo_set_font_size(bot.cr, g.fs);
        draw_bottom(bot.cr, &g, sc, s, w, h);
        if (band_close(&bot, rgba, w) != 0)
            rc = core_err_set(err, -1, "render: HUD: cairo failed drawing the head-up strip");
    }
    return rc;
}

void render_overlay_hud_bands(int w, int h, int *top_px, int *bottom_px)
{
    hud_geom g;
    hud_geom_make(w, h, &g);
    if (top_px)
        *top_px = g.top_h;
    if (bottom_px)
        *bottom_px = g.bot_h;
}
