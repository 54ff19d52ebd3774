/* test_render.c -- the scene and the cameras (render/scene.c, camera.c,
 * view.c).
 *
 * A synthetic state (no sim/, no log): the CG-47 rolled, pitched, yawed
 * and moved in E on a sea of one sinusoid, a UH-60A (hfm geometry of
 * scenarios/aircraft/uh60a.ini) off the stern, approaching. Checks:
 *  - render_project puts known points (1 m inside each deck corner, the
 *    spot's centre, the horizon bar, the rotor hub, the CG, the sea far
 *    from the ship, the sky) on pixels that show their colour, for each
 *    camera. A colour "matches" when the pixel is k times the table colour
 *    (render_colour_rgb) within 12 levels a channel, k in the lighting's
 *    range (ambient 0.4 to full sun 1.0, less a little haze; unlit lights
 *    at 1). The deck and the hull are both grey, so a deck pixel must also
 *    share the spot's k (both face up under the same sun) within 0.08.
 *  - golden images, 160 x 120, one per camera (tests/render/golden/;
 *    regenerate with `test_render --update-golden`, run from the
 *    repository root, and look at them). Tolerance: at most 0.5 % of the
 *    pixels may differ by more than 24 levels in any channel, and at most
 *    2 % by more than 6. llvmpipe is deterministic for one Mesa/LLVM
 *    build, but another build may round fog, lighting or an edge pixel
 *    differently: a few levels everywhere and a few moved edges (0.5 % is
 *    96 pixels) pass, while a moved camera or a missing part (many pixels
 *    by far more than 24) and a surface's colour changed by more than 6
 *    levels (the deck is 5 to 10 % of the pilot's and overhead views) do
 *    not.
 *  - the same state renders to identical bytes twice, and in a second
 *    context; the sea function is called once a frame.
 *  - bad views, bad cameras and a missing eye give clear errors.
 *  - the still deck view of `disim render` (render_deck_view): sky above,
 *    sea below, the deck at the look-at point, starboard on the right; PNG
 *    written atomically and read back; bad sizes refused.
 * `test_render --dump DIR` also writes each camera at 640 x 480 to look at. */
#include "check.h"
#include "render.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

enum { W = 320, H = 200 };
enum { GW = 160, GH = 120 };

static const uint8_t *px(const uint8_t *img, int x, int y) { return img + 4 * ((size_t)y * W + x); }

static int is_orange(const uint8_t *p) { return p[0] > 200 && p[1] > 100 && p[1] < 180 && p[2] < 60; }

/* ------------------------------------------------------------ sea */
typedef struct sea_user {
    int calls, n;
    int mode;                     /* 0 the sinusoid, 1 refuse (< 0: a flat sea), 2 a NaN */
    double x0, x1, y0, y1;        /* the points' extent in the last call */
} sea_user;

#define SEA_AMP_M 0.8
#define SEA_K_PER_M (2.0 * CORE_PI / 80.0)
#define SEA_W_RADPS 0.88

static double sea_eta(double t, double x, double y) { return SEA_AMP_M * sin(SEA_K_PER_M * (0.8 * x + 0.6 * y) - SEA_W_RADPS * t); }

static int sea_fn(void *user, double t_s, int n, const double *x, const double *y, double *eta)
{
    sea_user *u = user;
    u->calls++;
    u->n = n;
    u->x0 = u->y0 = INFINITY;
    u->x1 = u->y1 = -INFINITY;
    for (int i = 0; i < n; i++) {
        eta[i] = u->mode == 2 && i == n / 2 ? NAN : sea_eta(t_s, x[i], y[i]);
        u->x0 = fmin(u->x0, x[i]), u->x1 = fmax(u->x1, x[i]);
        u->y0 = fmin(u->y0, y[i]), u->y1 = fmax(u->y1, y[i]);
    }
    return u->mode == 1 ? -1 : 0;
}

/* ------------------------------------------------------------ state */
static void make_state(render_state *s)
{
    memset(s, 0, sizeof *s);
    s->t_s = 3.0;
    core_euler es = {6.0 * CORE_DEG_TO_RAD, 1.5 * CORE_DEG_TO_RAD, 25.0 * CORE_DEG_TO_RAD};
    s->ship.pos_E_m = core_vec3_make(30.0, -12.0, 0.4);
    s->ship.q_EF = core_quat_from_euler(es);
    s->ship_yaw_rad = es.psi_rad;
    s->have_heli = 1;
    double cg_S[3] = {-25.0, 3.0, -9.0}, cg_E[3];
    render_S_to_E(s, cg_S, cg_E);
    s->heli.pos_E_m = core_vec3_make(cg_E[0], cg_E[1], cg_E[2]);
    core_euler eb = {-2.0 * CORE_DEG_TO_RAD, 3.0 * CORE_DEG_TO_RAD, 30.0 * CORE_DEG_TO_RAD};
    s->heli.q_EF = core_quat_from_euler(eb);
    s->roll_rad = eb.phi_rad, s->pitch_rad = eb.theta_rad, s->yaw_rad = eb.psi_rad;
    memcpy(s->pos_S_m, cg_S, sizeof cg_S);
    s->rotor_azimuth_rad = 0.3;
    for (int i = 0; i < 4; i++)
        s->controls_pct[i] = 50.0;
}

/* ------------------------------------------------------------ colours */
/* Pixel p of image img (w wide) against colour c: k = the least-squares
 * scale, the largest channel residual; 1 when k is in [kmin, kmax] and the
 * residual at most tol. */
static int matches(const uint8_t *p, render_colour c, double kmin, double kmax, double tol, double *k_out)
{
    uint8_t rgb[3];
    render_colour_rgb(c, rgb);
    double num = 0, den = 0;
    for (int i = 0; i < 3; i++)
        num += (double)p[i] * rgb[i], den += (double)rgb[i] * rgb[i];
    double k = den > 0 ? num / den : 0, res = 0;
    for (int i = 0; i < 3; i++)
        res = fmax(res, fabs(p[i] - k * rgb[i]));
    if (k_out)
        *k_out = k;
    return k >= kmin && k <= kmax && res <= tol;
}
#define LIT_MIN 0.36
#define LIT_MAX 1.02
#define TOL 12.0

static const uint8_t *at(const uint8_t *img, int w, const double p[2])
{
    return img + 4 * ((size_t)(int)p[1] * w + (int)p[0]);
}

/* Project p_E in a w x h frame; NULL (and a failed check) if not inside. */
static const uint8_t *pixel_of(const render_view *v, int w, int h, const uint8_t *img, const double p_E[3],
                               const char *what, const char *cam)
{
    double q[2], depth;
    int r = render_project(v, w, h, p_E, q, &depth);
    if (r != 0) {
        fprintf(stderr, "  %s camera: %s projects outside the image (%d)\n", cam, what, r);
        CHECK(r == 0);
        return NULL;
    }
    const uint8_t *c = at(img, w, q);
    printf("  %-8s %-22s px (%6.1f, %6.1f) depth %7.1f m  rgb %3d %3d %3d\n", cam, what, q[0], q[1], depth, c[0],
           c[1], c[2]);
    return c;
}

static void expect(const uint8_t *p, render_colour c, double kmin, double kmax, const char *what)
{
    double k = 0;
    int ok = p && matches(p, c, kmin, kmax, TOL, &k);
    if (!ok && p)
        fprintf(stderr, "  %s: rgb %d %d %d is not colour %d (k %.3f)\n", what, p[0], p[1], p[2], (int)c, k);
    CHECK(ok);
}

/* Sky: between the horizon's and the zenith's colours, blue. */
static void expect_sky(const uint8_t *p, const char *what)
{
    uint8_t hz[3], zn[3];
    render_colour_rgb(RENDER_COLOUR_SKY_HORIZON, hz);
    render_colour_rgb(RENDER_COLOUR_SKY_ZENITH, zn);
    int ok = p != NULL;
    for (int i = 0; ok && i < 3; i++) {
        int lo = hz[i] < zn[i] ? hz[i] : zn[i], hi = hz[i] < zn[i] ? zn[i] : hz[i];
        ok = p[i] >= lo - 3 && p[i] <= hi + 3;
    }
    if (!ok && p)
        fprintf(stderr, "  %s: rgb %d %d %d is not sky\n", what, p[0], p[1], p[2]);
    CHECK(ok && p[2] > p[0] + 30);
}

/* The deck's four corners 1 m inside, and the spot: the spot's k is the
 * deck's (both face up). */
static void expect_deck(const render_view *v, int w, int h, const uint8_t *img, const render_state *s,
                        const core_ship *sh, const char *cam, int corners)
{
    double o_S[3] = {0, 0, 0}, o_E[3], k_spot = 0;
    render_S_to_E(s, o_S, o_E);
    const uint8_t *p = pixel_of(v, w, h, img, o_E, "spot centre", cam);
    int ok = p && matches(p, RENDER_COLOUR_SPOT, LIT_MIN, LIT_MAX, TOL, &k_spot);
    if (!ok && p)
        fprintf(stderr, "  %s: spot centre rgb %d %d %d is not the spot's colour\n", cam, p[0], p[1], p[2]);
    CHECK(ok);
    for (int c = 0; c < 4; c++) {
        if (!(corners >> c & 1))
            continue;
        double cs[3] = {c & 1 ? sh->deck_x1_m - 1.0 : sh->deck_x0_m + 1.0,
                        c & 2 ? sh->deck_halfwidth_m - 1.0 : -sh->deck_halfwidth_m + 1.0, 0.0},
               ce[3], k = 0;
        char what[40];
        snprintf(what, sizeof what, "deck corner %s %s", c & 1 ? "fwd" : "aft", c & 2 ? "stbd" : "port");
        render_S_to_E(s, cs, ce);
        const uint8_t *q = pixel_of(v, w, h, img, ce, what, cam);
        int okc = q && matches(q, RENDER_COLOUR_DECK, LIT_MIN, LIT_MAX, TOL, &k) && fabs(k - k_spot) < 0.08;
        if (!okc && q)
            fprintf(stderr, "  %s: %s rgb %d %d %d: not the deck (k %.3f, the spot's %.3f)\n", cam, what, q[0], q[1],
                    q[2], k, k_spot);
        CHECK(okc);
    }
}

/* The horizon bar (scene.c: 0.35 m above the hangar face's top edge, half
 * the hangar's width long, 0.3 m tall, level in E): its centre and points
 * 0.45 of its length either side along E's horizontal. With the ship rolled
 * 6 deg, a bar that rolled with it would put its ends 0.3 m off them. */
static void expect_horizon_bar(const render_view *v, int w, int h, const uint8_t *img, const render_state *s,
                               const core_ship *sh, const char *cam)
{
    const core_ship_block *hg = NULL;
    for (int i = 0; i < sh->nblocks; i++)
        if (strcmp(sh->blocks[i].name, "hangar") == 0)
            hg = &sh->blocks[i];
    CHECK(hg != NULL);
    if (!hg)
        return;
    double c_S[3] = {hg->x0_m - 0.08, 0.5 * (hg->y0_m + hg->y1_m), hg->z0_m - 0.35}, c[3], o[3], x1[3];
    double o_S[3] = {0, 0, 0}, x_S[3] = {1, 0, 0}, bar[3];
    render_S_to_E(s, c_S, c);
    render_S_to_E(s, o_S, o);
    render_S_to_E(s, x_S, x1);
    /* horizontal, normal to the bow: (0, 0, 1) x x_S */
    bar[0] = -(x1[1] - o[1]), bar[1] = x1[0] - o[0], bar[2] = 0;
    double n = hypot(bar[0], bar[1]), half = fmin(0.25 * (hg->y1_m - hg->y0_m), 3.0);
    for (int k = -1; k <= 1; k++) {
        double p[3];
        for (int i = 0; i < 3; i++)
            p[i] = c[i] + k * 0.9 * half * bar[i] / n;
        char what[32];
        snprintf(what, sizeof what, "horizon bar %s", k < 0 ? "port end" : k > 0 ? "stbd end" : "centre");
        expect(pixel_of(v, w, h, img, p, what, cam), RENDER_COLOUR_HORIZON_BAR, 0.85, 1.05, what);
    }
}

static void sea_point(const render_state *s, const double xy_E[2], double p[3], double deck_h)
{
    p[0] = xy_E[0];
    p[1] = xy_E[1];
    p[2] = deck_h - sea_eta(s->t_s, xy_E[0], xy_E[1]);
}

/* A point far along direction az (from north) and elevation el from eye. */
static void sky_point(const double eye[3], double az_deg, double el_deg, double p[3])
{
    double az = az_deg * CORE_DEG_TO_RAD, el = el_deg * CORE_DEG_TO_RAD;
    p[0] = eye[0] + 2000.0 * cos(el) * cos(az);
    p[1] = eye[1] + 2000.0 * cos(el) * sin(az);
    p[2] = eye[2] - 2000.0 * sin(el);
}

/* ------------------------------------------------------------ golden */
static int golden_compare(const char *path, const uint8_t *img, int w, int h, int update)
{
    core_err err = {0};
    if (update) {
        int r = render_write_png(path, w, h, img, &err);
        printf("  wrote %s%s%s\n", path, r ? ": " : "", r ? err.msg : "");
        return r == 0;
    }
    int gw = 0, gh = 0;
    uint8_t *g = NULL;
    if (render_read_png(path, &gw, &gh, &g, &err) != 0) {
        fprintf(stderr, "  %s\n", err.msg);
        return 0;
    }
    long bad = 0, off = 0;
    int maxd = 0;
    if (gw == w && gh == h)
        for (long i = 0; i < (long)w * h; i++) {
            int d = 0;
            for (int c = 0; c < 3; c++)
                d = abs(img[4 * i + c] - g[4 * i + c]) > d ? abs(img[4 * i + c] - g[4 * i + c]) : d;
            bad += d > 24;
            off += d > 6;
            maxd = d > maxd ? d : maxd;
        }
    free(g);
    double frac = (double)bad / ((double)w * h), frac6 = (double)off / ((double)w * h);
    printf("  golden %s: %.3f %% of the pixels differ by more than 24 levels (limit 0.5 %%), %.3f %% by more "
           "than 6 (limit 2 %%), largest %d\n", path, 100.0 * frac, 100.0 * frac6, maxd);
    return gw == w && gh == h && frac <= 0.005 && frac6 <= 0.02;
}

/* ------------------------------------------------------------ checks */
static void test_cameras(const render_scene *sc, sea_user *su, const char *dump_dir, int update)
{
    core_err err = {0};
    render_state s;
    make_state(&s);
    const int w = 640, h = 480;
    render_ctx *rc = render_create(w, h, &err);
    render_ctx *rg = render_create(GW, GH, &err);
    CHECK(rc && rg);
    if (!rc || !rg) {
        render_destroy(rc);
        render_destroy(rg);
        return;
    }
    uint8_t *img = malloc((size_t)4 * w * h), *img2 = malloc((size_t)4 * w * h);
    const core_ship *sh = sc->ship;
    const hfm_geometry *g = sc->heli;
    double cg[3] = {s.heli.pos_E_m.x, s.heli.pos_E_m.y, s.heli.pos_E_m.z}, hub[3];
    render_B_to_E(&s, g->hub_B_m, hub);
    for (int k = 0; k < RENDER_CAM_COUNT; k++) {
        const char *name = render_camera_name((render_camera_kind)k);
        render_view v;
        CHECK(render_camera_place((render_camera_kind)k, sc, &s, &v, &err) == 0);
        su->calls = 0;
        int r = render_frame(rc, sc, &s, &v, img, &err);
        CHECK(r == 0);
        if (r) {
            fprintf(stderr, "  %s: %s\n", name, err.msg);
            continue;
        }
        /* One call of the sea function a frame, with the whole grid. */
        CHECK(su->calls == 1 && su->n >= 64 * 64);
        switch (k) {
        case RENDER_CAM_PILOT: {
            /* Ahead and below: the deck of the ship the helicopter approaches. */
            expect_deck(&v, w, h, img, &s, sh, name, 0xa); /* the forward corners */
            double p[3];
            sky_point(v.eye_E_m, 30.0 + 25.0, 8.0, p);
            expect_sky(pixel_of(&v, w, h, img, p, "sky 25 deg right", name), "pilot sky");
            expect_horizon_bar(&v, w, h, img, &s, sh, name);
            break;
        }
        case RENDER_CAM_DECK: {
            /* The officer looks at the CG: the middle of the image, the cabin. */
            expect(pixel_of(&v, w, h, img, cg, "CG", name), RENDER_COLOUR_FUSELAGE, LIT_MIN, LIT_MAX, "deck: CG");
            double q[2];
            CHECK(render_project(&v, w, h, cg, q, NULL) == 0 && fabs(q[0] - w / 2.0) < 1 && fabs(q[1] - h / 2.0) < 1);
            double p[3];
            sky_point(v.eye_E_m, 25.0 + 180.0 + 30.0, 40.0, p);
            expect_sky(pixel_of(&v, w, h, img, p, "sky astern, 40 deg up", name), "deck sky");
            break;
        }
        case RENDER_CAM_CHASE: {
            const uint8_t *p = pixel_of(&v, w, h, img, hub, "rotor hub", name);
            int ok = p && (matches(p, RENDER_COLOUR_ROTOR, LIT_MIN, LIT_MAX, TOL, NULL) ||
                           matches(p, RENDER_COLOUR_FUSELAGE, LIT_MIN, LIT_MAX, TOL, NULL));
            CHECK(ok);
            /* The sea 200 m ahead and 120 m to port of the helicopter. */
            double psi = s.yaw_rad, xy[2] = {cg[0] + 200 * cos(psi) + 120 * sin(psi),
                                             cg[1] + 200 * sin(psi) - 120 * cos(psi)}, sp[3];
            sea_point(&s, xy, sp, sh->deck_height_m);
            expect(pixel_of(&v, w, h, img, sp, "sea 200 m ahead, port", name), RENDER_COLOUR_SEA, 0.3, 1.2,
                   "chase: sea");
            double k[3];
            sky_point(v.eye_E_m, psi * CORE_RAD_TO_DEG - 20.0, 6.0, k);
            expect_sky(pixel_of(&v, w, h, img, k, "sky ahead", name), "chase sky");
            break;
        }
        case RENDER_CAM_OVERHEAD: {
            expect_deck(&v, w, h, img, &s, sh, name, 0xf);
            /* The sea 15 m off the starboard side abreast the spot, and the
             * horizon bar on the hangar's top edge (unlit, k = 1). */
            double ps[3] = {0.0, sh->beam_m / 2.0 + 7.0, 0.0}, pe[3], sp[3];
            render_S_to_E(&s, ps, pe);
            sea_point(&s, pe, sp, sh->deck_height_m);
            expect(pixel_of(&v, w, h, img, sp, "sea abeam", name), RENDER_COLOUR_SEA, 0.3, 1.2, "overhead: sea");
            break;
        }
        }
        if (dump_dir) {
            char path[512];
            snprintf(path, sizeof path, "%s/%s.png", dump_dir, name);
            CHECK(render_write_png(path, w, h, img, &err) == 0);
        }
        /* The same state twice: the same bytes. */
        CHECK(render_frame(rc, sc, &s, &v, img2, &err) == 0);
        CHECK(memcmp(img, img2, (size_t)4 * w * h) == 0);
        /* Golden images at 160 x 120. */
        uint8_t *gi = malloc((size_t)4 * GW * GH);
        CHECK(render_frame(rg, sc, &s, &v, gi, &err) == 0);
        char gp[256];
        snprintf(gp, sizeof gp, "tests/render/golden/%s.png", name);
        CHECK(golden_compare(gp, gi, GW, GH, update));
        free(gi);
    }
    /* A second context renders the same bytes as the first. */
    render_view v;
    CHECK(render_camera_place(RENDER_CAM_CHASE, sc, &s, &v, &err) == 0);
    render_ctx *r2 = render_create(w, h, &err);
    CHECK(r2 != NULL);
    if (r2) {
        CHECK(render_frame(rc, sc, &s, &v, img, &err) == 0);
        CHECK(render_frame(r2, sc, &s, &v, img2, &err) == 0);
        CHECK(memcmp(img, img2, (size_t)4 * w * h) == 0);
    }
    render_destroy(r2);

    /* The ship turned 90 deg more: the ship-fixed overhead camera sees the
     * same deck, the deck camera without a helicopter looks at the spot. */
    render_state s2 = s;
    core_euler e2 = {6.0 * CORE_DEG_TO_RAD, 1.5 * CORE_DEG_TO_RAD, 115.0 * CORE_DEG_TO_RAD};
    s2.ship.q_EF = core_quat_from_euler(e2);
    s2.have_heli = 0;
    CHECK(render_camera_place(RENDER_CAM_OVERHEAD, sc, &s2, &v, &err) == 0);
    CHECK(render_frame(rc, sc, &s2, &v, img, &err) == 0);
    expect_deck(&v, w, h, img, &s2, sh, "overhead (ship turned)", 0xf);
    CHECK(render_camera_place(RENDER_CAM_DECK, sc, &s2, &v, &err) == 0);
    CHECK(render_frame(rc, sc, &s2, &v, img, &err) == 0);
    expect_deck(&v, w, h, img, &s2, sh, "deck, no helicopter", 0);
    free(img);
    free(img2);
    render_destroy(rc);
    render_destroy(rg);
}

/* The sea grid about the ship in E (the points span at least 300 m either
 * side of it); its waves shade the sea (a flat sea, the function refusing,
 * changes many pixels of the chase view, all of them sea); a NaN
 * elevation is an error. */
static void test_sea(const render_scene *sc, sea_user *su)
{
    core_err err = {0};
    const int w = 160, h = 120;
    render_ctx *rc = render_create(w, h, &err);
    uint8_t *a = malloc((size_t)4 * w * h), *b = malloc((size_t)4 * w * h);
    render_state s;
    make_state(&s);
    /* 2.5 km from E's origin: the grid must follow the ship. */
    s.ship.pos_E_m.x += 2000.0, s.ship.pos_E_m.y += 1500.0;
    s.heli.pos_E_m.x += 2000.0, s.heli.pos_E_m.y += 1500.0;
    render_view v;
    CHECK(rc && render_camera_place(RENDER_CAM_CHASE, sc, &s, &v, &err) == 0);
    if (!rc) {
        free(a), free(b);
        return;
    }
    su->mode = 0;
    CHECK(render_frame(rc, sc, &s, &v, a, &err) == 0);
    printf("  sea grid x %.0f to %.0f m, y %.0f to %.0f m (E); the ship at (%.0f, %.0f)\n", su->x0, su->x1, su->y0,
           su->y1, s.ship.pos_E_m.x, s.ship.pos_E_m.y);
    CHECK(su->x0 < s.ship.pos_E_m.x - 300 && su->x1 > s.ship.pos_E_m.x + 300);
    CHECK(su->y0 < s.ship.pos_E_m.y - 300 && su->y1 > s.ship.pos_E_m.y + 300);
    su->mode = 1;
    CHECK(render_frame(rc, sc, &s, &v, b, &err) == 0);
    long diff = 0, diff_not_sea = 0;
    for (long i = 0; i < (long)w * h; i++)
        if (memcmp(a + 4 * i, b + 4 * i, 3) != 0) {
            diff++;
            diff_not_sea += !matches(b + 4 * i, RENDER_COLOUR_SEA, 0.3, 1.2, TOL, NULL);
        }
    printf("  waves vs a flat sea: %ld pixels differ (%.1f %%), %ld of them not sea in the flat one\n", diff,
           100.0 * diff / (w * h), diff_not_sea);
    CHECK(diff > w * h / 10);
    CHECK(diff_not_sea < diff / 50);
    su->mode = 2;
    CHECK(render_frame(rc, sc, &s, &v, b, &err) < 0 && strstr(err.msg, "sea elevation") != NULL);
    su->mode = 0;
    free(a), free(b);
    render_destroy(rc);
}

/* The main rotor's blades at the state's azimuth, turning as rotor_ccw
 * says: seen from overhead, blade 1 at azimuth 20 deg lies aft and to
 * starboard for a counter-clockwise rotor (from aft toward starboard), to
 * port for a clockwise one; with 4 blades (20, 110, 200, 290 deg) nothing
 * lies at the mirror point. And the SA365N's fenestron: seen along its
 * axis, the dark fan inside a lighter duct ring. */
static void test_rotors(const render_scene *sc0)
{
    core_err err = {0};
    const int w = 320, h = 240;
    render_ctx *rc = render_create(w, h, &err);
    uint8_t *img = malloc((size_t)4 * w * h);
    CHECK(rc != NULL);
    if (!rc) {
        free(img);
        return;
    }
    render_state s;
    make_state(&s);
    double cg_S[3] = {0, 0, -12}, cg[3];
    render_S_to_E(&s, cg_S, cg);
    s.heli.pos_E_m = core_vec3_make(cg[0], cg[1], cg[2]);
    s.heli.q_EF = s.ship.q_EF; /* level with the deck, along the bow */
    s.rotor_azimuth_rad = 20.0 * CORE_DEG_TO_RAD;
    for (int ccw = 1; ccw >= 0; ccw--) {
        hfm_geometry g = *sc0->heli;
        g.rotor_ccw = ccw;
        render_scene sc = *sc0;
        sc.heli = &g;
        render_view v;
        CHECK(render_camera_place(RENDER_CAM_OVERHEAD, &sc, &s, &v, &err) == 0);
        CHECK(render_frame(rc, &sc, &s, &v, img, &err) == 0);
        double a = s.rotor_azimuth_rad, r = 0.7 * g.rotor_radius_m, p1_B[3], pm_B[3], p1[3], pm[3];
        double dir = ccw ? 1.0 : -1.0;
        for (int i = 0; i < 3; i++)
            p1_B[i] = pm_B[i] = g.hub_B_m[i];
        p1_B[0] += -r * cos(a), p1_B[1] += dir * r * sin(a);
        pm_B[0] += -r * cos(a), pm_B[1] -= dir * r * sin(a);
        render_B_to_E(&s, p1_B, p1);
        render_B_to_E(&s, pm_B, pm);
        const char *cam = ccw ? "overhead (ccw)" : "overhead (cw)";
        const uint8_t *b1 = pixel_of(&v, w, h, img, p1, "blade 1 at 20 deg", cam);
        const uint8_t *bm = pixel_of(&v, w, h, img, pm, "its mirror", cam);
        CHECK(b1 && matches(b1, RENDER_COLOUR_ROTOR, LIT_MIN, LIT_MAX, TOL, NULL));
        CHECK(bm && !matches(bm, RENDER_COLOUR_ROTOR, LIT_MIN, LIT_MAX, TOL, NULL));
    }
    hfm_aircraft *ac = hfm_aircraft_load("scenarios/aircraft/sa365n.ini", NULL, &err);
    CHECK(ac != NULL);
    if (ac) {
        hfm_geometry g;
        hfm_aircraft_geometry(ac, &g);
        CHECK(g.tail_fenestron == 1);
        render_scene sc = *sc0;
        sc.heli = &g;
        double th[3], ax_B[3], ax[3], o_B[3] = {0, 0, 0}, o[3], eye[3], ring_B[3], ring[3];
        render_B_to_E(&s, g.tail_hub_B_m, th);
        double n = sqrt(g.tail_dir_B[0] * g.tail_dir_B[0] + g.tail_dir_B[1] * g.tail_dir_B[1] +
                        g.tail_dir_B[2] * g.tail_dir_B[2]);
        for (int i = 0; i < 3; i++)
            ax_B[i] = g.tail_dir_B[i] / n;
        render_B_to_E(&s, ax_B, ax);
        render_B_to_E(&s, o_B, o);
        for (int i = 0; i < 3; i++)
            eye[i] = th[i] + 6.0 * (ax[i] - o[i]);
        /* A point of the duct ring: 1.12 radii up the fin from the hub. */
        memcpy(ring_B, g.tail_hub_B_m, sizeof ring_B);
        ring_B[2] -= 1.12 * g.tail_radius_m;
        render_B_to_E(&s, ring_B, ring);
        render_view v;
        CHECK(render_view_look_at(&v, eye, th, 30.0, &err) == 0);
        CHECK(render_frame(rc, &sc, &s, &v, img, &err) == 0);
        expect(pixel_of(&v, w, h, img, th, "fenestron's fan", "side"), RENDER_COLOUR_ROTOR, LIT_MIN, LIT_MAX,
               "fenestron fan");
        expect(pixel_of(&v, w, h, img, ring, "fenestron's duct", "side"), RENDER_COLOUR_HULL, 0.3, 0.82,
               "fenestron duct");
        hfm_aircraft_destroy(ac);
    }
    free(img);
    render_destroy(rc);
}

static void test_bad_views(const render_scene *sc)
{
    core_err err = {0};
    render_state s;
    make_state(&s);
    render_ctx *rc = render_create(64, 48, &err);
    uint8_t *img = malloc(4 * 64 * 48);
    render_view v, b;
    CHECK(rc && render_camera_place(RENDER_CAM_CHASE, sc, &s, &v, &err) == 0);
    if (!rc) {
        free(img);
        return;
    }
    CHECK(render_frame(rc, sc, &s, &v, img, &err) == 0);
    b = v;
    b.eye_E_m[1] = NAN;
    CHECK(render_frame(rc, sc, &s, &b, img, &err) < 0 && strstr(err.msg, "eye_E_m") != NULL);
    b = v;
    b.fov_y_deg = 0.5;
    CHECK(render_frame(rc, sc, &s, &b, img, &err) < 0 && strstr(err.msg, "fov_y_deg = 0.5") != NULL);
    b.fov_y_deg = 171;
    CHECK(render_frame(rc, sc, &s, &b, img, &err) < 0 && strstr(err.msg, "expected 1 to 170") != NULL);
    b = v;
    for (int i = 0; i < 3; i++)
        b.fwd_E[i] *= 2.0;
    CHECK(render_frame(rc, sc, &s, &b, img, &err) < 0 && strstr(err.msg, "fwd_E has length 2") != NULL);
    b = v;
    memcpy(b.up_E, b.fwd_E, sizeof b.up_E);
    CHECK(render_frame(rc, sc, &s, &b, img, &err) < 0 && strstr(err.msg, "orthogonal") != NULL);
    b = v;
    b.near_m = 0;
    CHECK(render_frame(rc, sc, &s, &b, img, &err) < 0 && strstr(err.msg, "near_m") != NULL);
    /* A NaN pose, and a missing scene. */
    render_state bs = s;
    bs.ship.q_EF.w = NAN;
    CHECK(render_frame(rc, sc, &bs, &v, img, &err) < 0 && strstr(err.msg, "ship's pose") != NULL);
    CHECK(render_frame(rc, NULL, &s, &v, img, &err) < 0);
    /* Look-at on its target; cameras by name; the pilot needs an eye. */
    CHECK(render_view_look_at(&b, v.eye_E_m, v.eye_E_m, 50, &err) < 0 && strstr(err.msg, "on target_E_m"));
    CHECK(render_view_look_at(&b, v.eye_E_m, v.fwd_E, 200, &err) < 0 && strstr(err.msg, "fov_y_deg"));
    render_camera_kind k;
    CHECK(render_camera_parse("overhead", &k, &err) == 0 && k == RENDER_CAM_OVERHEAD);
    CHECK(render_camera_parse("tower", &k, &err) < 0 && strstr(err.msg, "'tower'") && strstr(err.msg, "chase"));
    CHECK(strcmp(render_camera_name(RENDER_CAM_DECK), "deck") == 0);
    render_scene ns = *sc;
    ns.heli = NULL;
    CHECK(render_camera_place(RENDER_CAM_PILOT, &ns, &s, &b, &err) < 0 && strstr(err.msg, "pilot camera"));
    hfm_geometry noeye = *sc->heli;
    noeye.has_eye = 0;
    ns.heli = &noeye;
    CHECK(render_camera_place(RENDER_CAM_PILOT, &ns, &s, &b, &err) < 0 && strstr(err.msg, "pilot_eye_B_m"));
    /* render_project: a point behind, one off the image, the centre ahead. */
    double q[2], d, p[3];
    for (int i = 0; i < 3; i++)
        p[i] = v.eye_E_m[i] - 10.0 * v.fwd_E[i];
    CHECK(render_project(&v, 64, 48, p, q, &d) == -1 && d < 0);
    for (int i = 0; i < 3; i++)
        p[i] = v.eye_E_m[i] + 10.0 * v.fwd_E[i];
    CHECK(render_project(&v, 64, 48, p, q, &d) == 0 && fabs(q[0] - 32) < 1e-9 && fabs(q[1] - 24) < 1e-9);
    CHECK_NEAR(d, 10.0, 1e-9);
    /* Up in the view is up in the image (y down), right is right. */
    double r_E[3] = {v.fwd_E[1] * v.up_E[2] - v.fwd_E[2] * v.up_E[1], v.fwd_E[2] * v.up_E[0] - v.fwd_E[0] * v.up_E[2],
                     v.fwd_E[0] * v.up_E[1] - v.fwd_E[1] * v.up_E[0]};
    for (int i = 0; i < 3; i++)
        p[i] = v.eye_E_m[i] + 10.0 * v.fwd_E[i] + 1.0 * v.up_E[i] + 1.0 * r_E[i];
    CHECK(render_project(&v, 64, 48, p, q, &d) == 0 && q[1] < 24 && q[0] > 32);
    for (int i = 0; i < 3; i++)
        p[i] = v.eye_E_m[i] + 10.0 * v.fwd_E[i] + 30.0 * r_E[i];
    CHECK(render_project(&v, 64, 48, p, q, &d) == 1);
    /* The horizon: the chase camera stays level (its right axis
     * horizontal), the ship-fixed deck camera rolls with the ship (6 deg). */
    render_view dv;
    CHECK(render_camera_place(RENDER_CAM_DECK, sc, &s, &dv, &err) == 0);
    double rc_z = v.fwd_E[0] * v.up_E[1] - v.fwd_E[1] * v.up_E[0];
    double rd_z = dv.fwd_E[0] * dv.up_E[1] - dv.fwd_E[1] * dv.up_E[0];
    printf("  right axis z_E: chase %.2g, deck %.3f (ship roll 6 deg)\n", rc_z, rd_z);
    CHECK(fabs(rc_z) < 1e-12);
    CHECK(fabs(rd_z) > sin(3.0 * CORE_DEG_TO_RAD));
    int w = 0, h = 0;
    render_size(rc, &w, &h);
    CHECK(w == 64 && h == 48);
    free(img);
    render_destroy(rc);
}

static void test_deck_view(void)
{
    core_ship ship;
    core_err err = {0};
    CHECK(core_ship_load("scenarios/ships/sfs2.ini", &ship, &err) == 0);
    render_ctx *rc = render_create(W, H, &err);
    CHECK(rc != NULL);
    if (!rc)
        return;
    uint8_t *img = malloc(4 * W * H);
    /* From astern on the centre line, looking at a deck point 3 m to starboard
     * of the spot (off the white markings); the helicopter marker 5 m to
     * starboard, 6 m up. */
    render_camera cam = {{-60, 0, -10}, {0, 3, 0}, 40.0};
    double heli[3] = {0, 5, -6};
    CHECK(render_deck_view(rc, &ship, &cam, heli, img, &err) == 0);
    const uint8_t *sky = px(img, W / 2, 2), *centre = px(img, W / 2, H / 2);
    const uint8_t *sea = px(img, 2, H - 3);
    CHECK(sky[2] > 200 && sky[0] < 180); /* light blue */
    /* The deck's colour at the look-at point, lit from above. */
    expect(centre, RENDER_COLOUR_DECK, 0.6, LIT_MAX, "deck view: centre");
    expect(sea, RENDER_COLOUR_SEA, 0.3, 1.2, "deck view: sea");
    CHECK(sea[2] > sea[0] + 40); /* dark blue */
    /* Starboard is on the right: the marker's pixels lie right of the centre. */
    long sx = 0, n = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            if (is_orange(px(img, x, y)))
                sx += x, n++;
    CHECK(n > 10);
    CHECK(n > 0 && sx / n > W / 2);
    /* Up is up: the hangar face (12 m forward, 7.6 m tall) rises above the
     * deck in the image: the pixel straight above the centre, a third of the
     * way up, is ship grey, not sky. */
    const uint8_t *hangar = px(img, W / 2, H / 2 - H / 6);
    CHECK(!(hangar[2] > 200 && hangar[0] < 180));

    const char *png = "render_test.png";
    remove(png);
    CHECK(render_write_png(png, W, H, img, &err) == 0);
    FILE *f = fopen(png, "rb");
    unsigned char sig[8] = {0};
    CHECK(f && fread(sig, 1, 8, f) == 8);
    if (f)
        fclose(f);
    CHECK(memcmp(sig, "\x89PNG\r\n\x1a\n", 8) == 0);
    /* Read back: the same pixels. */
    int rw = 0, rh = 0;
    uint8_t *back = NULL;
    CHECK(render_read_png(png, &rw, &rh, &back, &err) == 0 && rw == W && rh == H);
    CHECK(back && memcmp(back, img, (size_t)4 * W * H) == 0);
    free(back);
    CHECK(render_read_png("/nonexistent-dir/x.png", &rw, &rh, &back, &err) < 0 && back == NULL);
    CHECK(strstr(err.msg, "/nonexistent-dir/x.png") != NULL);
    CHECK(render_write_png("/nonexistent-dir/x.png", W, H, img, &err) < 0);
    CHECK(strstr(err.msg, "/nonexistent-dir/x.png") != NULL);
    remove(png);

    /* A path longer than the old fixed 1024-byte temporary name: the PNG
     * must go through path.tmp, not through the truncated name (here a
     * file of the user's, which was overwritten and renamed away). */
    char base[] = "/tmp/disim_test_render_XXXXXX";
    CHECK(mkdtemp(base) != NULL);
    char longp[1100], cut[1100];
    snprintf(longp, sizeof longp, "%s", base);
    while (strlen(longp) < 900) { /* then a last name of 70 to 130 bytes */
        strcat(longp, "/dddddddddddddddddddddddddddddddddddddddddddddddddd");
        CHECK(mkdir(longp, 0700) == 0);
    }
    size_t pad = 1027 - strlen(longp) - strlen("/.png");
    strcat(longp, "/");
    memset(longp + strlen(longp), 'v', pad);
    longp[1027 - 4] = '\0';
    strcat(longp, ".png");
    CHECK(strlen(longp) == 1027);
    snprintf(cut, sizeof cut, "%.1023s", longp); /* the old tmp name */
    f = fopen(cut, "w");
    CHECK(f && fputs("keep me", f) >= 0);
    if (f)
        fclose(f);
    CHECK(render_write_png(longp, W, H, img, &err) == 0);
    f = fopen(cut, "rb");
    char kept[16] = {0};
    CHECK(f && fread(kept, 1, sizeof kept - 1, f) == 7 && strcmp(kept, "keep me") == 0);
    if (f)
        fclose(f);
    f = fopen(longp, "rb");
    memset(sig, 0, sizeof sig);
    CHECK(f && fread(sig, 1, 8, f) == 8 && memcmp(sig, "\x89PNG\r\n\x1a\n", 8) == 0);
    if (f)
        fclose(f);
    char cmd[64];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", base);
    CHECK(system(cmd) == 0);

    /* A camera on its target: an error, not an image of sky (NaN view). */
    render_camera on = {{5, 3, -2}, {5, 3, -2}, 40.0};
    err.msg[0] = '\0';
    CHECK(render_deck_view(rc, &ship, &on, NULL, img, &err) < 0);
    CHECK(strstr(err.msg, "target_S_m") != NULL);

    cam.fov_y_deg = 0.0;
    CHECK(render_deck_view(rc, &ship, &cam, NULL, img, &err) < 0);
    CHECK(render_create(4, 4, &err) == NULL);
    CHECK(strstr(err.msg, "4x4") != NULL);
    render_destroy(NULL);
    render_destroy(rc);
    free(img);
}

int main(int argc, char **argv)
{
    int update = 0;
    const char *dump = NULL;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--update-golden") == 0)
            update = 1;
        else if (strcmp(argv[i], "--dump") == 0 && i + 1 < argc)
            dump = argv[++i];
        else {
            fprintf(stderr, "usage: test_render [--update-golden] [--dump DIR]\n");
            return 2;
        }
    }
    core_err err = {0};
    core_ship ship;
    CHECK(core_ship_load("scenarios/ships/cg47.ini", &ship, &err) == 0);
    hfm_aircraft *ac = hfm_aircraft_load("scenarios/aircraft/uh60a.ini", NULL, &err);
    CHECK(ac != NULL);
    if (!ac) {
        fprintf(stderr, "%s\n", err.msg);
        return check_done("test_render");
    }
    hfm_geometry geo;
    hfm_aircraft_geometry(ac, &geo);
    sea_user su = {0};
    render_scene sc = {.ship = &ship, .heli = &geo, .sea = sea_fn, .sea_user = &su};
    test_cameras(&sc, &su, dump, update);
    test_sea(&sc, &su);
    test_rotors(&sc);
    test_bad_views(&sc);
    test_deck_view();
    hfm_aircraft_destroy(ac);
    return check_done("test_render");
}
