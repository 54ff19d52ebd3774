/* test_render_video.c -- the overlays and the video writer: the overlay
 * list parsed; the head-up strip drawn in its bands only, with text, bars
 * and the height of the lowest wheel over the deck; the airwake slice
 * sampled where it should be, coloured by the diverging map, clear outside
 * the field, cached per scene, drawn blended and depth-tested without depth
 * writes; MP4s through ffmpeg (skipped where it is not installed: exit 77,
 * and a failure with CI set: check_skip)
 * with the right frame count, size and colours, nothing at PATH before
 * close, odd sizes, two videos at once, a missing directory, abort, and an
 * ffmpeg that dies (an error, not a SIGPIPE death). */
#include "check.h"
#include "render.h"
#include "render/render_priv.h"

#include <dirent.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>


/* ---------------------------------------------------------------- parse */
static void test_parse(void)
{
    core_err err = {0};
    unsigned b = 99;
    CHECK(render_overlays_parse("hud", &b, &err) == 0 && b == RENDER_OVERLAY_HUD);
    CHECK(render_overlays_parse("airwake", &b, &err) == 0 && b == RENDER_OVERLAY_AIRWAKE);
    CHECK(render_overlays_parse("hud,airwake", &b, &err) == 0 && b == (RENDER_OVERLAY_HUD | RENDER_OVERLAY_AIRWAKE));
    CHECK(render_overlays_parse("airwake, hud", &b, &err) == 0 && b == (RENDER_OVERLAY_HUD | RENDER_OVERLAY_AIRWAKE));
    b = 99;
    CHECK(render_overlays_parse("none", &b, &err) == 0 && b == 0);
    b = 7;
    err.msg[0] = '\0';
    CHECK(render_overlays_parse("hud,smoke", &b, &err) < 0 && strstr(err.msg, "\"smoke\"") && b == 7);
    err.msg[0] = '\0';
    CHECK(render_overlays_parse("hudx", &b, &err) < 0 && strstr(err.msg, "\"hudx\""));
    CHECK(render_overlays_parse("", &b, &err) < 0);
    CHECK(render_overlays_parse("hud,", &b, &err) < 0);
    CHECK(render_overlays_parse("none,hud", &b, &err) < 0);
}

/* ------------------------------------------------------------------ HUD */
static void fill(uint8_t *img, int w, int h, uint8_t grey)
{
    for (size_t k = 0; k < (size_t)w * h; k++) {
        img[4 * k] = img[4 * k + 1] = img[4 * k + 2] = grey;
        img[4 * k + 3] = 255;
    }
}

/* Pixels of rows [y0, y1) and columns [x0, x1) that differ between a and b. */
static long n_diff(const uint8_t *a, const uint8_t *b, int w, int x0, int x1, int y0, int y1)
{
    long n = 0;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++)
            n += memcmp(a + 4 * ((size_t)y * w + x), b + 4 * ((size_t)y * w + x), 4) != 0;
    return n;
}

/* Bright (text) and dark (background) pixels in a region. */
static void count_tones(const uint8_t *img, int w, int x0, int x1, int y0, int y1, long *bright, long *dark)
{
    *bright = *dark = 0;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) {
            const uint8_t *p = img + 4 * ((size_t)y * w + x);
            if (p[1] > 180)
                (*bright)++;
            else if (p[0] < 80 && p[1] < 80 && p[2] < 80)
                (*dark)++;
        }
}

static hfm_geometry heli_geom(void)
{
    hfm_geometry g;
    memset(&g, 0, sizeof g);
    snprintf(g.name, sizeof g.name, "test");
    g.blades = 4;
    g.rotor_radius_m = 8.0;
    g.hub_B_m[2] = -1.5;
    g.gear.nlegs = 2;
    /* Two wheels 1.5 m either side, 1.5 m below the CG, tyres 0.3 m. */
    double legs[2][3] = {{0, 1.5, 1.5}, {0, -1.5, 1.5}};
    for (int k = 0; k < 2; k++) {
        memcpy(g.gear.leg[k].pos_B_m, legs[k], sizeof legs[k]);
        g.gear.leg[k].tyre_radius_m = 0.3;
    }
    return g;
}

static core_ship test_ship(void)
{
    core_ship s;
    memset(&s, 0, sizeof s);
    snprintf(s.name, sizeof s.name, "test");
    s.length_m = 120;
    s.beam_m = 14;
    s.deck_height_m = 6;
    s.deck_x0_m = -12;
    s.deck_x1_m = 12;
    s.deck_halfwidth_m = 7;
    return s;
}

/* A state: the ship at ship_E with attitude identity, the helicopter's CG
 * at cg_E rolled by roll_rad. */
static render_state test_state(const double ship_E[3], const double cg_E[3], double roll_rad)
{
    render_state s;
    memset(&s, 0, sizeof s);
    s.t_s = 12.5;
    s.ship.pos_E_m = core_vec3_make(ship_E[0], ship_E[1], ship_E[2]);
    s.ship.q_EF = core_quat_identity();
    s.have_heli = 1;
    s.heli.pos_E_m = core_vec3_make(cg_E[0], cg_E[1], cg_E[2]);
    core_euler e = {roll_rad, 0, 0};
    s.heli.q_EF = core_quat_from_euler(e);
    for (int i = 0; i < 3; i++)
        s.pos_S_m[i] = cg_E[i] - ship_E[i];
    s.vel_S_mps[0] = 1.2;
    s.vel_S_mps[2] = 0.4;
    s.roll_rad = roll_rad;
    s.pitch_rad = 3 * CORE_DEG_TO_RAD;
    s.yaw_rad = 10 * CORE_DEG_TO_RAD;
    s.controls_pct[0] = 55;
    s.controls_pct[1] = 48;
    s.controls_pct[2] = 51;
    s.controls_pct[3] = 45;
    s.rotor_thrust_N = 72000;
    return s;
}

static void test_hud_size(int W, int H)
{
    core_ship ship = test_ship();
    hfm_geometry g = heli_geom();
    render_scene sc = {.ship = &ship, .heli = &g, .overlays = RENDER_OVERLAY_HUD, .title = "cg47_uh60a landing"};
    double ship_E[3] = {0, 0, 6}, cg_E[3] = {1, 2, -2};
    render_state s = test_state(ship_E, cg_E, 0.0);
    render_view v = {{0, 0, -10}, {1, 0, 0}, {0, 0, -1}, 60, 0.5, 2000};
    core_err err = {0};
    uint8_t *img = malloc((size_t)4 * W * H), *ref = malloc((size_t)4 * W * H);
    fill(img, W, H, 128);
    memcpy(ref, img, (size_t)4 * W * H);
    int top = 0, bot = 0;
    render_overlay_hud_bands(W, H, &top, &bot);
    CHECK(top > 8 && bot > 3 * 8 && top + bot < H / 3);
    CHECK(render_overlay_hud(&sc, &s, &v, W, H, img, &err) == 0);
    /* Only the bands change: the rows between them are the caller's. */
    CHECK(n_diff(img, ref, W, 0, W, top, H - bot) == 0);
    /* The bands are darkened all across (the background)... */
    CHECK(n_diff(img, ref, W, 0, W, H - bot, H) > (long)W * bot * 9 / 10);
    CHECK(n_diff(img, ref, W, 0, W, 0, top) > (long)W * top * 9 / 10);
    /* ...with text on it: the attitudes' column (its first 12 characters)
     * has white or green text pixels and dark background both. */
    long bright, dark;
    int colw = (int)(0.602 * fmin(H / 36.0, W / 54.0) * 12);
    count_tones(img, W, 0, colw, H - bot, H, &bright, &dark);
    CHECK(bright > colw * bot / 40);
    CHECK(dark > colw * bot / 4);
    count_tones(img, W, 0, colw, 0, top, &bright, &dark); /* the time */
    CHECK(bright > colw * top / 40 && dark > colw * top / 4);
    /* The image's alpha is kept. */
    int alpha_kept = 1;
    for (size_t k = 0; k < (size_t)W * H; k++)
        alpha_kept &= img[4 * k + 3] == 255;
    CHECK(alpha_kept);

    /* The values are drawn: other controls change the controls' part of the
     * strip (the right half) and not the attitudes' column. */
    uint8_t *img2 = malloc((size_t)4 * W * H);
    fill(img2, W, H, 128);
    render_state s2 = s;
    s2.controls_pct[0] = 95;
    s2.controls_pct[3] = 5;
    CHECK(render_overlay_hud(&sc, &s2, &v, W, H, img2, &err) == 0);
    CHECK(n_diff(img, img2, W, W / 2, W, H - bot, H) > 20);
    CHECK(n_diff(img, img2, W, 0, colw, H - bot, H) == 0);
    /* The state: ON DECK and CRASH on the right of the top band. */
    fill(img2, W, H, 128);
    s2 = s;
    s2.on_deck = 1;
    s2.flags = 64u | 512u;
    CHECK(render_overlay_hud(&sc, &s2, &v, W, H, img2, &err) == 0);
    CHECK(n_diff(img, img2, W, W / 2, W, 0, top) > 20);
    CHECK(n_diff(img, img2, W, 0, W, H - bot, H) == 0);
    uint8_t *img3 = malloc((size_t)4 * W * H); /* ON DECK alone: CRASH was drawn */
    fill(img3, W, H, 128);
    s2.flags = 64u;
    CHECK(render_overlay_hud(&sc, &s2, &v, W, H, img3, &err) == 0);
    CHECK(n_diff(img3, img2, W, W / 2, W, 0, top) > 20);
    free(img3);

    /* No overlay: nothing drawn. The airwake alone: its legend, top band
     * only. */
    fill(img2, W, H, 128);
    sc.overlays = 0;
    CHECK(render_overlay_hud(&sc, &s, &v, W, H, img2, &err) == 0);
    CHECK(n_diff(img2, ref, W, 0, W, 0, H) == 0);
    sc.overlays = RENDER_OVERLAY_AIRWAKE;
    sc.air_ref_mps = 10;
    sc.air = NULL;
    CHECK(render_overlay_hud(&sc, &s, &v, W, H, img2, &err) == 0); /* no field: no legend */
    CHECK(n_diff(img2, ref, W, 0, W, 0, H) == 0);
    free(img);
    free(ref);
    free(img2);
}

/* The height over the deck: the lowest wheel's bottom above the deck plane,
 * read back from what the HUD would print is not possible, so through the
 * same transforms: the CG 8 m above the spot (ship origin at z_E = 6, CG at
 * z_E = -2), wheels 1.5 m below the CG, tyres 0.3 m: 6.2 m level; rolled
 * 30 deg, the starboard wheel is lowest, 1.5 (sin 30 + cos 30) = 2.049 m
 * below the CG: 8 - 2.049 - 0.3 = 5.651 m. */
static void test_height(void)
{
    core_ship ship = test_ship();
    hfm_geometry g = heli_geom();
    render_scene sc = {.ship = &ship, .heli = &g};
    double ship_E[3] = {3, -1, 6}, cg_E[3] = {4, 1, -2};
    render_state s = test_state(ship_E, cg_E, 0.0);
    CHECK_NEAR(render_overlay_deck_height(&sc, &s), 6.2, 1e-9);
    s = test_state(ship_E, cg_E, 30 * CORE_DEG_TO_RAD);
    CHECK_NEAR(render_overlay_deck_height(&sc, &s), 8 - 1.5 * (0.5 + sqrt(3) / 2) - 0.3, 1e-9);
    s = test_state(ship_E, cg_E, -30 * CORE_DEG_TO_RAD); /* the port wheel, the same height */
    CHECK_NEAR(render_overlay_deck_height(&sc, &s), 8 - 1.5 * (0.5 + sqrt(3) / 2) - 0.3, 1e-9);
    g.gear.nlegs = 0; /* no gear: the CG's height */
    CHECK_NEAR(render_overlay_deck_height(&sc, &s), 8.0, 1e-9);
}

/* -------------------------------------------------------------- airwake */
/* A synthetic airwake in S: 10 m/s from the bow; a deficit to 5 m/s over
 * the deck behind the hangar (x_S in [-12, 12], |y_S| < 6), an excess to
 * 15 m/s far astern (x_S < -40), and outside the field beyond |y_S| = 30. */
typedef struct air_case {
    long calls;
    double z_seen;
} air_case;

static int air_fn(void *user, const double p[3], double v[3])
{
    air_case *a = user;
    a->calls++;
    a->z_seen = p[2];
    if (fabs(p[1]) > 30)
        return 1;
    double u = 10;
    if (p[0] > -12 && p[0] < 12 && fabs(p[1]) < 6)
        u = 5;
    else if (p[0] < -40)
        u = 15;
    v[0] = -u;
    v[1] = 0;
    v[2] = 0;
    return 0;
}

static int air_fail(void *user, const double p[3], double v[3])
{
    (void)user, (void)p, (void)v;
    return -1;
}

static int rgb_is(const uint8_t *p, int r, int g, int b, int tol)
{
    return abs(p[0] - r) <= tol && abs(p[1] - g) <= tol && abs(p[2] - b) <= tol;
}

/* The legend of the airwake's colours: in the top band on the right, with
 * the map's blue and red ends; without the HUD, nothing else drawn. */
static void test_legend(void)
{
    enum { W = 640, H = 480 };
    core_ship ship = test_ship();
    air_case a = {0, 0};
    render_scene sc = {.ship = &ship, .air = air_fn, .air_user = &a, .air_ref_mps = 10,
                       .overlays = RENDER_OVERLAY_AIRWAKE};
    double ship_E[3] = {0, 0, 6}, cg_E[3] = {1, 2, -2};
    render_state s = test_state(ship_E, cg_E, 0.0);
    render_view v = {{0, 0, -10}, {1, 0, 0}, {0, 0, -1}, 60, 0.5, 2000};
    core_err err = {0};
    uint8_t *img = malloc(4 * W * H), *ref = malloc(4 * W * H);
    fill(img, W, H, 128);
    memcpy(ref, img, 4 * W * H);
    int top = 0, bot = 0;
    render_overlay_hud_bands(W, H, &top, &bot);
    CHECK(render_overlay_hud(&sc, &s, &v, W, H, img, &err) == 0);
    CHECK(n_diff(img, ref, W, 0, W, top, H) == 0);
    CHECK(n_diff(img, ref, W, 0, W / 4, 0, top) == 0); /* boxed on the right only */
    long blue = 0, red = 0;
    for (int y = 0; y < top; y++)
        for (int x = W / 2; x < W; x++) {
            const uint8_t *p = img + 4 * ((size_t)y * W + x);
            blue += rgb_is(p, 59, 76, 192, 12);
            red += rgb_is(p, 180, 4, 38, 12);
        }
    CHECK(blue > 4 && red > 4);
    CHECK(a.calls == 0); /* the legend samples nothing */
    free(img);
    free(ref);
}

static const uint8_t *texel(const render_ctx *rc, double x, double y)
{
    int i = (int)floor((x - rc->slice_x0_m) / (rc->slice_x1_m - rc->slice_x0_m) * rc->slice_nx);
    int j = (int)floor((y - rc->slice_y0_m) / (rc->slice_y1_m - rc->slice_y0_m) * rc->slice_ny);
    return rc->slice_rgba + 4 * ((size_t)j * rc->slice_nx + i);
}

static void test_colour_map(void)
{
    uint8_t c[3];
    render_overlay_air_colour(1.0 - RENDER_AIR_SPAN, c);
    CHECK(rgb_is(c, 59, 76, 192, 0)); /* deficit: Moreland's blue end */
    render_overlay_air_colour(1.0, c);
    CHECK(rgb_is(c, 221, 221, 221, 0)); /* the free stream: grey */
    render_overlay_air_colour(1.0 + RENDER_AIR_SPAN, c);
    CHECK(rgb_is(c, 180, 4, 38, 0)); /* excess: the red end */
    render_overlay_air_colour(0.0, c);
    CHECK(rgb_is(c, 59, 76, 192, 0)); /* clamped */
    render_overlay_air_colour(1.0 - 0.5 * RENDER_AIR_SPAN, c);
    CHECK(rgb_is(c, 141, 176, 254, 0)); /* the table's quarter point */
    render_overlay_air_colour(NAN, c);
    CHECK(rgb_is(c, 59, 76, 192, 0));
}

static void test_slice(void)
{
    core_err err = {0};
    core_ship ship = test_ship();
    hfm_geometry g = heli_geom();
    air_case a = {0, 0};
    render_scene sc = {.ship = &ship, .heli = &g, .air = air_fn, .air_user = &a, .air_ref_mps = 10,
                       .overlays = RENDER_OVERLAY_AIRWAKE};
    double ship_E[3] = {0, 0, 0}, cg_E[3] = {-5, 0, -8};
    render_state s = test_state(ship_E, cg_E, 0.0);
    render_ctx *rc = render_create(128, 128, &err);
    CHECK(rc != NULL);
    if (!rc)
        return;
    CHECK(render_overlay_air_sample(rc, &sc, &s, &err) == 0);
    /* The plane: x from the deck's aft end - 40 to its forward end + 10, y
     * within +-(beam + 20), at the hub's height (CG 8 m up, hub 1.5 m above
     * it), every 0.5 m. */
    CHECK_NEAR(rc->slice_x0_m, -52, 1e-12);
    CHECK_NEAR(rc->slice_x1_m, 22, 1e-12);
    CHECK_NEAR(rc->slice_y0_m, -34, 1e-12);
    CHECK_NEAR(rc->slice_y1_m, 34, 1e-12);
    CHECK_NEAR(rc->slice_z_m, -9.5, 1e-9);
    CHECK_NEAR(a.z_seen, -9.5, 1e-9);
    CHECK(rc->slice_nx == 148 && rc->slice_ny == 136);
    CHECK(a.calls == (long)rc->slice_nx * rc->slice_ny);
    const uint8_t *p = texel(rc, 0, 0); /* the deficit: blue, half opaque */
    CHECK(rgb_is(p, 59, 76, 192, 0) && p[3] == 128);
    p = texel(rc, 15, 10); /* the free stream: grey */
    CHECK(rgb_is(p, 221, 221, 221, 0) && p[3] == 128);
    p = texel(rc, -45, 0); /* the excess: red */
    CHECK(rgb_is(p, 180, 4, 38, 0) && p[3] == 128);
    p = texel(rc, 0, 32); /* outside the field: clear */
    CHECK(p[3] == 0);
    p = texel(rc, 0, -32);
    CHECK(p[3] == 0);
    /* Sampled once per scene: another state (higher) neither samples again
     * nor moves the plane. */
    long calls = a.calls;
    double cg2[3] = {-5, 0, -15};
    render_state s2 = test_state(ship_E, cg2, 0.0);
    CHECK(render_overlay_air_sample(rc, &sc, &s2, &err) == 0);
    CHECK(a.calls == calls && rc->slice_z_m == -9.5);
    /* Another field is sampled again; a given plane is used. */
    air_case b = {0, 0};
    sc.air_user = &b;
    sc.air_slice_z_S_m = -4;
    CHECK(render_overlay_air_sample(rc, &sc, &s2, &err) == 0);
    CHECK(b.calls == (long)rc->slice_nx * rc->slice_ny && rc->slice_z_m == -4 && b.z_seen == -4);
    /* Bad input. */
    render_scene bad = sc;
    bad.air_ref_mps = 0;
    bad.air_user = &calls;
    CHECK(render_overlay_air_sample(rc, &bad, &s, &err) < 0 && strstr(err.msg, "air_ref_mps"));
    bad = sc;
    bad.air = NULL;
    CHECK(render_overlay_air_sample(rc, &bad, &s, &err) < 0);
    bad = sc;
    bad.air = air_fail;
    bad.air_user = &calls;
    CHECK(render_overlay_air_sample(rc, &bad, &s, &err) < 0 && strstr(err.msg, "failed"));

    /* Drawn in GL: from straight above (orthographic: image x = x_S from
     * x0 to x1, image y = y_S from y0 at the top to y1 at the bottom) over
     * a black background. */
    sc.air_user = &a;
    sc.air_slice_z_S_m = -4;
    render_overlay_free(rc);
    CHECK(OSMesaMakeCurrent(rc->gl, rc->buf, GL_UNSIGNED_BYTE, rc->w, rc->h));
    CHECK(render_overlay_air_sample(rc, &sc, &s, &err) == 0);
    double X0 = rc->slice_x0_m, X1 = rc->slice_x1_m, Y0 = rc->slice_y0_m, Y1 = rc->slice_y1_m;
    glViewport(0, 0, rc->w, rc->h);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(X0, X1, -Y1, -Y0, 1, 200);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glTranslated(0, 0, -100);
    glRotated(90, 1, 0, 0); /* GL's up (-z_E) toward the eye, east (y_E) down the image */
    rc->origin_E_m[0] = rc->origin_E_m[1] = rc->origin_E_m[2] = 0;
    glClearColor(0, 0, 0, 1);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_LIGHTING);
    /* An opaque green square 2 m above the slice over x_S in [14, 20],
     * y_S in [-20, -10]: the slice must not show through it. */
    glColor3ub(0, 255, 0);
    glBegin(GL_QUADS);
    double sq[4][2] = {{14, -20}, {20, -20}, {20, -10}, {14, -10}};
    for (int k = 0; k < 4; k++) {
        double pS[3] = {sq[k][0], sq[k][1], -6}, pE[3];
        render_S_to_E(&s, pS, pE);
        render_gl_vertex_E(rc, pE);
    }
    glEnd();
    CHECK(render_overlay_airwake(rc, &sc, &s, &err) == 0);
    /* A yellow square 2 m below the slice over x_S in [-5, 5], y_S in
     * [-3, 3], drawn after it: shows through (the slice writes no depth). */
    glColor3ub(255, 255, 0);
    glBegin(GL_QUADS);
    double sq2[4][2] = {{-5, -3}, {5, -3}, {5, 3}, {-5, 3}};
    for (int k = 0; k < 4; k++) {
        double pS[3] = {sq2[k][0], sq2[k][1], -2}, pE[3];
        render_S_to_E(&s, pS, pE);
        render_gl_vertex_E(rc, pE);
    }
    glEnd();
    glFinish();
    /* The pixel of S point (x, y): GL's rows run bottom up, image y = y_S
     * down from the top. */
#define GLPX(x, y)                                                                              \
    (rc->buf + 4 * ((size_t)(int)((Y1 - (y)) / (Y1 - Y0) * rc->h) * rc->w +                     \
                    (int)(((x) - X0) / (X1 - X0) * rc->w)))
    /* The free stream's grey at half alpha over black: 221 * 128 / 255. */
    CHECK(rgb_is(GLPX(15.0, 10.0), 111, 111, 111, 3));
    /* The red excess astern. */
    CHECK(rgb_is(GLPX(-45.0, 0.0), 90, 2, 19, 3));
    /* The deficit over the deck, off the yellow square: blue. */
    CHECK(rgb_is(GLPX(-9.0, 4.0), 30, 38, 96, 3));
    /* Outside the field: the black background. */
    CHECK(rgb_is(GLPX(0.0, 32.5), 0, 0, 0, 0));
    /* Under the green square: green only. */
    CHECK(rgb_is(GLPX(17.0, -15.0), 0, 255, 0, 0));
    /* The yellow square below the slice was not hidden by it. */
    CHECK(rgb_is(GLPX(0.0, 0.0), 255, 255, 0, 0));
    render_destroy(rc);
}

/* ---------------------------------------------------------------- video */
static char tmpdir[256];

static int n_entries(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, ".."))
            n++;
    closedir(d);
    return n;
}

static int exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* ffprobe's width, height and decoded frame count of a video. */
static int probe(const char *path, int *w, int *h, long *frames)
{
    char cmd[1024];
    snprintf(cmd, sizeof cmd,
             "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
             "stream=width,height,nb_read_frames -of default=noprint_wrappers=1 '%s'",
             path);
    FILE *f = popen(cmd, "r");
    if (!f)
        return -1;
    char line[256];
    *w = *h = -1;
    *frames = -1;
    while (fgets(line, sizeof line, f)) {
        sscanf(line, "width=%d", w);
        sscanf(line, "height=%d", h);
        sscanf(line, "nb_read_frames=%ld", frames);
    }
    return pclose(f) == 0 ? 0 : -1;
}

/* The first frame decoded back to RGB: its centre pixel. */
static int first_pixel(const char *path, int w, int h, uint8_t rgb[3])
{
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "ffmpeg -nostdin -v error -i '%s' -frames:v 1 -f rawvideo -pix_fmt rgb24 -", path);
    FILE *f = popen(cmd, "r");
    if (!f)
        return -1;
    size_t n = (size_t)3 * w * h;
    uint8_t *buf = malloc(n);
    size_t got = fread(buf, 1, n, f);
    int rc = pclose(f);
    if (got == n)
        memcpy(rgb, buf + 3 * ((size_t)(h / 2) * w + w / 2), 3);
    free(buf);
    return got == n && rc == 0 ? 0 : -1;
}

static void frame_colour(uint8_t *img, int w, int h, int k)
{
    for (size_t i = 0; i < (size_t)w * h; i++) {
        img[4 * i] = 200;
        img[4 * i + 1] = (uint8_t)(40 + 6 * k);
        img[4 * i + 2] = 60;
        img[4 * i + 3] = 255;
    }
}

static void encode(const char *name, int w, int h, int n, int ew, int eh)
{
    core_err err = {0};
    char path[512];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    render_video *v = render_video_open(path, w, h, 30, &err);
    CHECK(v != NULL);
    if (!v) {
        fprintf(stderr, "%s\n", err.msg);
        return;
    }
    uint8_t *img = malloc((size_t)4 * w * h);
    for (int k = 0; k < n; k++) {
        frame_colour(img, w, h, k);
        CHECK(render_video_frame(v, img, &err) == 0);
    }
    CHECK(!exists(path)); /* only after close */
    CHECK(render_video_close(v, &err) == 0);
    CHECK(exists(path));
    int pw, ph;
    long pf;
    CHECK(probe(path, &pw, &ph, &pf) == 0);
    CHECK(pw == ew && ph == eh && pf == n);
    uint8_t rgb[3] = {0, 0, 0};
    CHECK(first_pixel(path, ew, eh, rgb) == 0);
    CHECK(rgb_is(rgb, 200, 40, 60, 10)); /* R and B not swapped; frame 0 first */
    free(img);
    remove(path);
}

static void test_video(void)
{
    if (!render_video_available()) {
        check_skip("the video checks: no ffmpeg with libx264 on PATH (go.sh installs it)");
        return;
    }
    const char *t = getenv("TMPDIR");
    snprintf(tmpdir, sizeof tmpdir, "%s/disim-video-XXXXXX", t && t[0] ? t : "/tmp");
    CHECK(mkdtemp(tmpdir) != NULL);
    core_err err = {0};
    /* A close that waits for ever (an ffmpeg that never sees the end of its
     * input) ends the test here rather than at CTest's timeout. */
    alarm(120);

    encode("a.mp4", 64, 48, 30, 64, 48);
    encode("odd.mp4", 63, 47, 30, 64, 48); /* padded to even sides */
    CHECK(n_entries(tmpdir) == 0);         /* no temporaries left */

    /* Two at once (the live renderer's cameras): the first closes while the
     * second is open; it would wait for ever if the second ffmpeg held the
     * first one's pipe. */
    char p1[512], p2[512];
    snprintf(p1, sizeof p1, "%s/one.mp4", tmpdir);
    snprintf(p2, sizeof p2, "%s/two.mp4", tmpdir);
    uint8_t img[4 * 64 * 48];
    render_video *v1 = render_video_open(p1, 64, 48, 25, &err);
    render_video *v2 = render_video_open(p2, 64, 48, 25, &err);
    CHECK(v1 && v2);
    if (v1 && v2) {
        for (int k = 0; k < 5; k++) {
            frame_colour(img, 64, 48, k);
            CHECK(render_video_frame(v1, img, &err) == 0);
            CHECK(render_video_frame(v2, img, &err) == 0);
        }
        CHECK(render_video_close(v1, &err) == 0);
        CHECK(render_video_close(v2, &err) == 0);
        CHECK(exists(p1) && exists(p2));
    }
    remove(p1);
    remove(p2);

    /* A missing directory: an error naming the path, nothing made. */
    char bad[600];
    snprintf(bad, sizeof bad, "%s/missing/v.mp4", tmpdir);
    err.msg[0] = '\0';
    CHECK(render_video_open(bad, 64, 48, 30, &err) == NULL);
    CHECK(strstr(err.msg, bad) != NULL);
    CHECK(n_entries(tmpdir) == 0);
    CHECK(render_video_open(p1, 64, 48, 0, &err) == NULL && strstr(err.msg, "fps"));
    CHECK(render_video_open(p1, 0, 48, 30, &err) == NULL);
    CHECK(n_entries(tmpdir) == 0);

    /* Abort: nothing left. */
    render_video *va = render_video_open(p1, 64, 48, 30, &err);
    CHECK(va != NULL);
    for (int k = 0; va && k < 5; k++)
        CHECK(render_video_frame(va, img, &err) == 0);
    render_video_abort(va);
    CHECK(n_entries(tmpdir) == 0);

    /* Closed without a frame: an error, nothing left. */
    render_video *v0 = render_video_open(p1, 64, 48, 30, &err);
    CHECK(v0 && render_video_close(v0, &err) < 0 && strstr(err.msg, p1));
    CHECK(n_entries(tmpdir) == 0);

    /* An ffmpeg that dies: a fake one on PATH that says why and exits. The
     * frames after its death are an error naming the file and carrying its
     * message; SIGPIPE (default: death) must not reach the process. */
    char bindir[512], fake[600];
    snprintf(bindir, sizeof bindir, "%s.bin", tmpdir);
    CHECK(mkdir(bindir, 0755) == 0);
    snprintf(fake, sizeof fake, "%s/ffmpeg", bindir);
    FILE *f = fopen(fake, "w");
    CHECK(f != NULL);
    if (f) {
        fputs("#!/bin/sh\necho 'fake ffmpeg: cannot encode' >&2\nexit 3\n", f);
        fclose(f);
    }
    CHECK(chmod(fake, 0755) == 0);
    const char *old = getenv("PATH");
    char *saved = strdup(old ? old : "/usr/bin:/bin");
    char newpath[4096];
    snprintf(newpath, sizeof newpath, "%s:%s", bindir, saved);
    setenv("PATH", newpath, 1);
    signal(SIGPIPE, SIG_DFL);
    render_video *vd = render_video_open(p1, 64, 48, 30, &err);
    CHECK(vd != NULL);
    int failed_at = -1;
    for (int k = 0; vd && k < 20000; k++) {
        if (render_video_frame(vd, img, &err) != 0) {
            failed_at = k;
            break;
        }
        if (k % 50 == 49)
            usleep(10000);
    }
    CHECK(failed_at >= 0);
    CHECK(strstr(err.msg, p1) && strstr(err.msg, "fake ffmpeg: cannot encode"));
    if (failed_at < 0)
        fprintf(stderr, "no frame failed\n");
    else
        printf("test_render_video: a dead ffmpeg: frame %d failed: %s\n", failed_at, err.msg);
    CHECK(vd && render_video_frame(vd, img, &err) < 0); /* and the next */
    CHECK(vd && render_video_close(vd, &err) < 0 && strstr(err.msg, p1));
    CHECK(n_entries(tmpdir) == 0);
    setenv("PATH", saved, 1);
    free(saved);
    remove(fake);
    rmdir(bindir);
    rmdir(tmpdir);
    alarm(0);
}

int main(void)
{
    test_parse();
    test_hud_size(640, 480);
    test_hud_size(1280, 720);
    test_height();
    test_colour_map();
    test_legend();
    test_slice();
    test_video();
    return check_done("test_render_video");
}
