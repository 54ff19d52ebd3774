/* otw_peer.c -- the other side of otw_view.sh, on the library's default LCM
 * URL (run only inside a private network namespace):
 *   peer SECONDS READY STOP [SCENARIO]
 *                        publishes one fixed state (the one below) as the
 *                        loop does, heli_state_t then ship_state_t of the
 *                        same utime, at 50 Hz, and counts the station's
 *                        pilot_input_t, for SECONDS or until the file STOP
 *                        exists, and with SCENARIO its run_info_t (as
 *                        the loop builds it) once a second; READY is
 *                        created once it listens;
 *                        prints "inputs N", "gaps G", "last_coll C"
 *   check SCENARIO PNG CAMERA
 *                        the screenshot PNG (the window at its top-left
 *                        corner) against what the state puts where: the
 *                        landing spot and the deck's forward corners, the
 *                        ship's horizon bar (its centre and both ends), the
 *                        sky, and the head-up strip's two bands (the scene
 *                        under them darkened); pixel colours at positions
 *                        computed with render_camera_place and
 *                        render_project, no golden image. Exit 0 if all hold.
 * The state is test_render's: the CG-47 rolled 6 deg, pitched 1.5, yawed
 * 25, the UH-60A 25 m aft of the spot, 3 m to starboard, 9 m above the
 * deck, yawed 30 deg: the pilot sees the deck ahead and below and the
 * hangar's face with the horizon bar. */
#include "check.h"
#include "disim_lcm.h"
#include "render.h"
#include "sim.h"

#include <lcm/lcm.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static const double SHIP_E_M[3] = {30.0, -12.0, 0.4};
static const double SHIP_EUL_DEG[3] = {6.0, 1.5, 25.0};
static const double HELI_S_M[3] = {-25.0, 3.0, -9.0};
static const double HELI_EUL_DEG[3] = {-2.0, 3.0, 30.0};

/* The state as the view builds it from the two messages. */
static void make_state(render_state *s)
{
    memset(s, 0, sizeof *s);
    s->t_s = 3.0;
    core_euler es = {SHIP_EUL_DEG[0] * CORE_DEG_TO_RAD, SHIP_EUL_DEG[1] * CORE_DEG_TO_RAD,
                     SHIP_EUL_DEG[2] * CORE_DEG_TO_RAD};
    s->ship.pos_E_m = core_vec3_make(SHIP_E_M[0], SHIP_E_M[1], SHIP_E_M[2]);
    s->ship.q_EF = core_quat_from_euler(es);
    s->ship_yaw_rad = es.psi_rad;
    s->have_heli = 1;
    double cg_E[3];
    render_S_to_E(s, HELI_S_M, cg_E);
    s->heli.pos_E_m = core_vec3_make(cg_E[0], cg_E[1], cg_E[2]);
    core_euler eb = {HELI_EUL_DEG[0] * CORE_DEG_TO_RAD, HELI_EUL_DEG[1] * CORE_DEG_TO_RAD,
                     HELI_EUL_DEG[2] * CORE_DEG_TO_RAD};
    s->heli.q_EF = core_quat_from_euler(eb);
    s->roll_rad = eb.phi_rad, s->pitch_rad = eb.theta_rad, s->yaw_rad = eb.psi_rad;
    memcpy(s->pos_S_m, HELI_S_M, sizeof s->pos_S_m);
    for (int i = 0; i < 4; i++)
        s->controls_pct[i] = 50.0;
}

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* ------------------------------------------------------------ the peer */
typedef struct inputs {
    long n, gaps;
    int64_t last_seq;
    double last_coll;
} inputs;

static void on_input(const lcm_recv_buf_t *rb, const char *ch, const disim_pilot_input_t *m, void *user)
{
    (void)rb, (void)ch;
    inputs *in = user;
    if (in->n > 0 && m->seq != in->last_seq + 1)
        in->gaps++;
    in->n++;
    in->last_seq = m->seq;
    in->last_coll = m->collective_pct;
}

/* The run information of scenario path as the loop publishes it: 0, or 1. */
static int run_info(const char *path, disim_run_info_t *m, sim_run_info *ri)
{
    sim_scenario *sc = calloc(1, sizeof *sc);
    core_err err;
    if (!sc || sim_scenario_load(path, sc, &err) != 0) {
        fprintf(stderr, "otw_peer: %s\n", sc ? err.msg : "out of memory");
        free(sc);
        return 1;
    }
    sim_world_overrides ov;
    sim_world_overrides_default(&ov);
    sim_world_run_info(sc, &ov, ri);
    free(sc);
    memset(m, 0, sizeof *m);
    m->scenario_path = ri->scenario_path;
    m->scenario = ri->scenario;
    m->aircraft_path = ri->aircraft_path;
    m->ship_path = ri->ship_path;
    m->seed = (int64_t)ri->seed;
    m->sea_state = (int8_t)ri->sea.state;
    m->ship_speed_mps = ri->sea.ship_speed_mps;
    m->wave_dir_rad = ri->sea.wave_dir_rad;
    m->course_rad = ri->sea.course_rad;
    m->n_waves = ri->sea.n_waves;
    m->rate_hz = 200.0;
    m->state_rate_hz = 50.0;
    return 0;
}

static int peer(double seconds, const char *ready, const char *stop, const char *scenario)
{
    disim_run_info_t ri_msg;
    sim_run_info ri;
    if (scenario && run_info(scenario, &ri_msg, &ri) != 0)
        return 1;
    lcm_t *lc = lcm_create(NULL);
    if (!lc)
        return 1;
    inputs in = {0, 0, -1, 0.0};
    disim_pilot_input_t_subscription_t *sub = disim_pilot_input_t_subscribe(lc, DISIM_CH_PILOT_INPUT, on_input, &in);
    render_state s;
    make_state(&s);
    FILE *f = fopen(ready, "w");
    if (f)
        fclose(f);
    double t0 = now_s(), next = t0;
    for (int64_t k = 0; now_s() - t0 < seconds && access(stop, F_OK) != 0; k++) {
        if (scenario && k % 50 == 0) {
            ri_msg.utime = 3000000 + 20000 * k;
            ri_msg.seq = k / 50;
            disim_run_info_t_publish(lc, DISIM_CH_RUN_INFO, &ri_msg);
        }
        disim_heli_state_t h;
        memset(&h, 0, sizeof h);
        h.utime = 3000000 + 20000 * k;
        h.seq = k;
        h.pos_E_m[0] = s.heli.pos_E_m.x, h.pos_E_m[1] = s.heli.pos_E_m.y, h.pos_E_m[2] = s.heli.pos_E_m.z;
        memcpy(h.pos_S_m, s.pos_S_m, sizeof h.pos_S_m);
        h.quat_EB[0] = s.heli.q_EF.w, h.quat_EB[1] = s.heli.q_EF.x;
        h.quat_EB[2] = s.heli.q_EF.y, h.quat_EB[3] = s.heli.q_EF.z;
        h.roll_rad = s.roll_rad, h.pitch_rad = s.pitch_rad, h.yaw_rad = s.yaw_rad;
        /* the flight's controls: a station whose window flies starts from these */
        h.collective_pct = 57.5;
        h.long_cyclic_pct = 46.25;
        h.lat_cyclic_pct = h.pedal_pct = 50.0;
        disim_heli_state_t_publish(lc, DISIM_CH_HELI_STATE, &h);
        disim_ship_state_t sh;
        memset(&sh, 0, sizeof sh);
        sh.utime = h.utime;
        sh.seq = k;
        sh.pos_E_m[0] = SHIP_E_M[0], sh.pos_E_m[1] = SHIP_E_M[1], sh.pos_E_m[2] = SHIP_E_M[2];
        sh.quat_ES[0] = s.ship.q_EF.w, sh.quat_ES[1] = s.ship.q_EF.x;
        sh.quat_ES[2] = s.ship.q_EF.y, sh.quat_ES[3] = s.ship.q_EF.z;
        sh.roll_rad = SHIP_EUL_DEG[0] * CORE_DEG_TO_RAD;
        sh.pitch_rad = SHIP_EUL_DEG[1] * CORE_DEG_TO_RAD;
        sh.yaw_rad = s.ship_yaw_rad;
        disim_ship_state_t_publish(lc, DISIM_CH_SHIP_STATE, &sh);
        next += 0.02;
        double wait;
        while ((wait = next - now_s()) > 0.0)
            lcm_handle_timeout(lc, (int)(wait * 1e3) + 1);
    }
    printf("inputs %ld\ngaps %ld\nlast_coll %.3f\n", in.n, in.gaps, in.last_coll);
    disim_pilot_input_t_unsubscribe(lc, sub);
    lcm_destroy(lc);
    return 0;
}

/* ------------------------------------------------------------ the checks */
/* Pixel p against colour c: k the least-squares scale within [kmin, kmax],
 * the largest channel residual within tol (as test_render). */
static int matches(const uint8_t *p, render_colour c, double kmin, double kmax, double tol)
{
    uint8_t rgb[3];
    render_colour_rgb(c, rgb);
    double num = 0, den = 0, res = 0;
    for (int i = 0; i < 3; i++)
        num += (double)p[i] * rgb[i], den += (double)rgb[i] * rgb[i];
    double k = den > 0 ? num / den : 0;
    for (int i = 0; i < 3; i++)
        res = fmax(res, fabs(p[i] - k * rgb[i]));
    return k >= kmin && k <= kmax && res <= tol;
}

typedef struct shot {
    const uint8_t *img;
    int w, h;             /* the screenshot's */
    int vw, vh;           /* the view's (the window's at the top-left corner) */
    const render_view *v;
} shot;

static const uint8_t *px(const shot *s, int x, int y) { return s->img + 4 * ((size_t)y * s->w + x); }

static void expect_at(const shot *s, const double p_E[3], render_colour c, double kmin, double kmax, const char *what)
{
    double q[2], depth;
    int r = render_project(s->v, s->vw, s->vh, p_E, q, &depth);
    if (r != 0) {
        fprintf(stderr, "  %s projects outside the view (%d)\n", what, r);
        CHECK(r == 0);
        return;
    }
    const uint8_t *p = px(s, (int)q[0], (int)q[1]);
    int ok = matches(p, c, kmin, kmax, 12.0);
    printf("  %-26s px (%6.1f, %6.1f) rgb %3d %3d %3d  %s\n", what, q[0], q[1], p[0], p[1], p[2], ok ? "ok" : "WRONG");
    CHECK(ok);
}

/* The ship's horizon bar (render/scene.c: level in E across the ship's
 * heading, 0.35 m above the hangar face's top edge, 0.08 m aft of it). */
static void expect_horizon_bar(const shot *s, const render_state *st, const core_ship *sh)
{
    const core_ship_block *hg = NULL;
    for (int i = 0; i < sh->nblocks; i++)
        if (!strcmp(sh->blocks[i].name, "hangar"))
            hg = &sh->blocks[i];
    CHECK(hg != NULL);
    if (!hg)
        return;
    double c_S[3] = {hg->x0_m - 0.08, 0.5 * (hg->y0_m + hg->y1_m), hg->z0_m - 0.35}, c[3], o[3], x1[3];
    double o_S[3] = {0, 0, 0}, x_S[3] = {1, 0, 0}, bar[3];
    render_S_to_E(st, c_S, c);
    render_S_to_E(st, o_S, o);
    render_S_to_E(st, x_S, x1);
    bar[0] = -(x1[1] - o[1]), bar[1] = x1[0] - o[0], bar[2] = 0;
    double n = hypot(bar[0], bar[1]), half = fmin(0.25 * (hg->y1_m - hg->y0_m), 3.0);
    for (int k = -1; k <= 1; k++) {
        double p[3];
        for (int i = 0; i < 3; i++)
            p[i] = c[i] + k * 0.8 * half * bar[i] / n;
        expect_at(s, p, RENDER_COLOUR_HORIZON_BAR, 0.85, 1.05,
                  k < 0 ? "horizon bar, port end" : k > 0 ? "horizon bar, stbd end" : "horizon bar, centre");
    }
}

/* The strip's bands: the scene under them at 0.45 of the brightness just
 * outside them, at the image's left and right edges (no text there). */
static void expect_bands(const shot *s)
{
    /* the bands' heights (render/overlay.c): font size fs = max(7, min(h / 36, w / 54)),
     * the top band 2.1 fs, the bottom strip 4.7 fs */
    double fs = fmax(7.0, fmin(s->vh / 36.0, s->vw / 54.0));
    int top = (int)ceil(2.1 * fs), bot = (int)ceil(4.7 * fs);
    const int probe[4][3] = {{1, 1, top + 2}, {s->vw - 2, 1, top + 2},
                             {1, s->vh - 2, s->vh - bot - 3}, {s->vw - 2, s->vh - 2, s->vh - bot - 3}};
    for (int i = 0; i < 4; i++) {
        const uint8_t *in = px(s, probe[i][0], probe[i][1]), *out = px(s, probe[i][0], probe[i][2]);
        double a = in[0] + in[1] + in[2], b = out[0] + out[1] + out[2], r = b > 0 ? a / b : 0;
        int ok = b > 60 && r > 0.3 && r < 0.6;
        printf("  strip %-6s %-5s  in rgb %3d %3d %3d, out rgb %3d %3d %3d: %.2f of it  %s\n",
               i < 2 ? "top" : "bottom", i % 2 ? "right" : "left", in[0], in[1], in[2], out[0], out[1], out[2], r,
               ok ? "ok" : "WRONG");
        CHECK(ok);
    }
}

static int check(const char *scenario, const char *png, const char *camera, int vw, int vh)
{
    core_err err = {0};
    render_camera_kind cam;
    sim_scenario *sc = calloc(1, sizeof *sc);
    core_ship ship;
    hfm_aircraft *ac = NULL;
    uint8_t *img = NULL;
    int w = 0, h = 0;
    if (!sc || render_camera_parse(camera, &cam, &err) || sim_scenario_load(scenario, sc, &err) ||
        core_ship_load(sc->ship_path, &ship, &err) || !(ac = hfm_aircraft_load(sc->aircraft_path, NULL, &err)) ||
        render_read_png(png, &w, &h, &img, &err)) {
        fprintf(stderr, "otw_peer check: %s\n", err.msg);
        free(sc);
        hfm_aircraft_destroy(ac);
        return 1;
    }
    CHECK(w >= vw && h >= vh);
    hfm_geometry g;
    hfm_aircraft_geometry(ac, &g);
    render_scene rs;
    memset(&rs, 0, sizeof rs);
    rs.ship = &ship;
    rs.heli = &g;
    render_state st;
    make_state(&st);
    render_view v;
    CHECK(render_camera_place(cam, &rs, &st, &v, &err) == 0);
    shot s = {img, w, h, vw, vh, &v};
    if (w >= vw && h >= vh) {
        double o_S[3] = {0, 0, 0}, o_E[3];
        render_S_to_E(&st, o_S, o_E);
        expect_at(&s, o_E, RENDER_COLOUR_SPOT, 0.36, 1.02, "landing spot");
        for (int k = 0; k < 2; k++) {
            double c_S[3] = {ship.deck_x1_m - 1.0, (k ? 1 : -1) * (ship.deck_halfwidth_m - 1.0), 0.0}, c_E[3];
            render_S_to_E(&st, c_S, c_E);
            expect_at(&s, c_E, RENDER_COLOUR_DECK, 0.36, 1.02, k ? "deck, fwd stbd corner" : "deck, fwd port corner");
        }
        expect_horizon_bar(&s, &st, &ship);
        expect_bands(&s);
    }
    free(img);
    hfm_aircraft_destroy(ac);
    free(sc);
    return check_done("otw_peer check");
}

int main(int argc, char **argv)
{
    if ((argc == 5 || argc == 6) && !strcmp(argv[1], "peer"))
        return peer(atof(argv[2]), argv[3], argv[4], argc == 6 ? argv[5] : NULL);
    if (argc == 7 && !strcmp(argv[1], "check"))
        return check(argv[2], argv[3], argv[4], atoi(argv[5]), atoi(argv[6]));
    fprintf(stderr, "usage: otw_peer peer SECONDS READY STOP [SCENARIO] | check SCENARIO PNG CAMERA VIEW_W VIEW_H\n");
    return 2;
}
