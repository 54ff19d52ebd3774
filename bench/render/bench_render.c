/* bench_render.c -- frames per second of the deck views (render_frame) with
 * the full scene: the CG-47 in sea state 4 (the sea drawn from the
 * seaway's elevation, sim_ship_motion_elevation), the UH-60A hovering 8 m
 * over the spot, the HUD overlay; each camera at 640 x 480 and 1280 x 720,
 * then the same with H.264 encoding through render_video (when an ffmpeg
 * that encodes H.264 is on PATH; the encoder is its own process and runs
 * beside the renderer), and with each frame written as PNG (render_write_png,
 * what disim fly --render does by default). Each case draws FRAMES frames
 * of a moving run (1/30 s apart), after 3 not timed, median of REPEATS.
 * Printed: frames/s of
 * wall time (what a viewer sees; llvmpipe draws with LP_NUM_THREADS
 * rasteriser threads, all cores by default), CPU ms per frame of this
 * process (all its threads: the rasteriser's work), and the ratio to the
 * targets: 640 x 480 at 60 frames/s, 1280 x 720 at 30, encoding included.
 * Usage: bench_render [FRAMES [CAMERA [WxH]]] from the source root (FRAMES
 * 30 by default; CAMERA and WxH fly that case alone, for a profile:
 * perf record). BENCH_RENDER_SPLIT=1 also times the parts of a frame
 * without the HUD and without the sea. */
#include "../bench.h"
#include "core.h"
#include "hfm.h"
#include "render.h"
#include "sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define REPEATS 5

typedef struct bench_run {
    const sim_ship_motion *motion;
    double omega_radps;
} bench_run;

/* The state at t_s: the ship as the seaway moves it, the helicopter 8 m
 * over the spot, heading with the ship, a little nose up. */
static void state_at(const bench_run *b, double t_s, render_state *s)
{
    memset(s, 0, sizeof *s);
    sim_ship_state st;
    sim_ship_motion_at(b->motion, t_s, &st);
    s->t_s = t_s;
    s->ship = st.pose;
    s->ship_yaw_rad = st.att.psi_rad;
    s->have_heli = 1;
    s->pos_S_m[0] = 0.5 * sin(0.3 * t_s);
    s->pos_S_m[2] = -8.0;
    s->heli.pos_E_m = core_pose_point_to_E(&st.pose, core_vec3_make(s->pos_S_m[0], s->pos_S_m[1], s->pos_S_m[2]));
    s->roll_rad = 0.02 * sin(t_s);
    s->pitch_rad = 0.05;
    s->yaw_rad = st.att.psi_rad;
    core_euler e = {s->roll_rad, s->pitch_rad, s->yaw_rad};
    s->heli.q_EF = core_quat_from_euler(e);
    s->controls_pct[0] = 55.0;
    s->controls_pct[1] = 48.0;
    s->controls_pct[2] = 51.0;
    s->controls_pct[3] = 47.0;
    s->rotor_thrust_N = 7.2e4;
    s->rotor_azimuth_rad = fmod(b->omega_radps * t_s, 2.0 * M_PI);
}

/* Frames per second (wall) and CPU s per frame of one case, the medians of
 * REPEATS; -1 on failure. out: 0 the frame alone, OUT_VIDEO encode each
 * frame through render_video (the close, which waits for ffmpeg to finish,
 * timed too), OUT_PNG write each as PNG. */
enum { OUT_NONE = 0, OUT_VIDEO = 1, OUT_PNG = 2 };
static int bench_case(const bench_run *b, const render_scene *sc, render_ctx *rc, render_camera_kind cam, int w,
                      int h, int frames, int out, const char *tmpdir, double *fps, double *cpu_s)
{
    double f[REPEATS], c[REPEATS];
    uint8_t *rgba = malloc((size_t)4 * w * h);
    if (!rgba)
        return -1;
    core_err err = {0};
    int bad = 0;
    for (int r = 0; r < REPEATS && !bad; r++) {
        render_video *v = NULL;
        char path[512];
        snprintf(path, sizeof path, "%s/bench_%s_%dx%d.%s", tmpdir, render_camera_name(cam), w, h,
                 out == OUT_VIDEO ? "mp4" : "png");
        double w0 = 0.0, c0 = 0.0;
        for (int i = -3; i < frames && !bad; i++) {
            if (i == 0) {
                w0 = core_monotonic_s();
                c0 = bench_cpu_s();
                if (out == OUT_VIDEO && !(v = render_video_open(path, w, h, 30.0, &err)))
                    bad = 1;
            }
            render_state s;
            state_at(b, 20.0 + (r * (frames + 3) + i + 3) / 30.0, &s);
            render_view view;
            if (bad || render_camera_place(cam, sc, &s, &view, &err) != 0 ||
                render_frame(rc, sc, &s, &view, rgba, &err) != 0 || (v && render_video_frame(v, rgba, &err) != 0) ||
                (out == OUT_PNG && i >= 0 && render_write_png(path, w, h, rgba, &err) != 0))
                bad = 1;
        }
        if (v && render_video_close(v, &err) != 0)
            bad = 1;
        remove(path);
        double wall = core_monotonic_s() - w0;
        f[r] = frames / wall;
        c[r] = (bench_cpu_s() - c0) / frames;
    }
    free(rgba);
    if (bad) {
        fprintf(stderr, "bench_render: %s %dx%d: %s\n", render_camera_name(cam), w, h, err.msg);
        return -1;
    }
    *fps = bench_median(f, REPEATS);
    *cpu_s = bench_median(c, REPEATS);
    return 0;
}

int main(int argc, char **argv)
{
    int frames = argc > 1 ? atoi(argv[1]) : 30;
    int only_cam = -1, only_w = 0, only_h = 0;
    if (frames < 1) {
        fprintf(stderr, "usage: bench_render [FRAMES [CAMERA [WxH]]]\n");
        return 2;
    }
    core_err err = {0};
    if (argc > 2) {
        render_camera_kind k;
        if (render_camera_parse(argv[2], &k, &err) != 0) {
            fprintf(stderr, "bench_render: %s\n", err.msg);
            return 2;
        }
        only_cam = (int)k;
    }
    if (argc > 3 && sscanf(argv[3], "%dx%d", &only_w, &only_h) != 2) {
        fprintf(stderr, "bench_render: '%s': expected WxH\n", argv[3]);
        return 2;
    }
    core_ship ship;
    if (core_ship_load("scenarios/ships/cg47.ini", &ship, &err) != 0) {
        fprintf(stderr, "bench_render: %s (run from the source root)\n", err.msg);
        return 1;
    }
    hfm_aircraft *ac = hfm_aircraft_load("scenarios/aircraft/uh60a.ini", NULL, &err);
    if (!ac) {
        fprintf(stderr, "bench_render: %s\n", err.msg);
        return 1;
    }
    hfm_geometry geo;
    hfm_aircraft_geometry(ac, &geo);
    sim_sea sea;
    sim_sea_default(&sea);
    sea.state = 4;
    sea.wave_dir_rad = 30.0 * CORE_DEG_TO_RAD;
    sim_ship_motion *m = sim_ship_motion_create(&ship, &sea, 2, &err);
    if (!m) {
        fprintf(stderr, "bench_render: %s\n", err.msg);
        hfm_aircraft_destroy(ac);
        return 1;
    }
    bench_run b = {m, geo.rotor_omega_radps};
    render_scene sc;
    memset(&sc, 0, sizeof sc);
    sc.ship = &ship;
    sc.heli = &geo;
    sc.sea = sim_ship_motion_elevation;
    sc.sea_user = m;
    sc.overlays = RENDER_OVERLAY_HUD;
    sc.title = "bench_render: CG-47 + UH-60A, sea state 4";
    char tmpdir[] = "/tmp/bench_render_XXXXXX";
    if (!mkdtemp(tmpdir)) {
        fprintf(stderr, "bench_render: cannot make a temporary folder\n");
        return 1;
    }
    int video = render_video_available();
    const char *lp = getenv("LP_NUM_THREADS");
    printf("bench_render: %d frames, median of %d; %ld cores, LP_NUM_THREADS %s; ffmpeg H.264 %s\n", frames, REPEATS,
           sysconf(_SC_NPROCESSORS_ONLN), lp ? lp : "unset (llvmpipe: one per core)", video ? "yes" : "no (encoding not timed)");
    printf("%-9s %-9s %9s %9s %9s %12s %9s %9s %10s %9s\n", "size", "camera", "frames/s", "cpu ms", "x target",
           "+H.264 f/s", "cpu ms", "x target", "+PNG f/s", "cpu ms");
    static const int sizes[2][2] = {{640, 480}, {1280, 720}};
    static const double target[2] = {60.0, 30.0};
    int rc = 0, split = getenv("BENCH_RENDER_SPLIT") != NULL;
    for (int z = 0; z < 2; z++) {
        int w = sizes[z][0], h = sizes[z][1];
        if (only_w && (w != only_w || h != only_h))
            continue;
        render_ctx *ctx = render_create(w, h, &err);
        if (!ctx) {
            fprintf(stderr, "bench_render: %s\n", err.msg);
            rc = 1;
            break;
        }
        for (int c = 0; c < RENDER_CAM_COUNT; c++) {
            if (only_cam >= 0 && c != only_cam)
                continue;
            double fps, cpu, vfps = 0.0, vcpu = 0.0, pfps, pcpu;
            render_camera_kind k = (render_camera_kind)c;
            if (bench_case(&b, &sc, ctx, k, w, h, frames, OUT_NONE, tmpdir, &fps, &cpu) != 0 ||
                (video && bench_case(&b, &sc, ctx, k, w, h, frames, OUT_VIDEO, tmpdir, &vfps, &vcpu) != 0) ||
                bench_case(&b, &sc, ctx, k, w, h, frames, OUT_PNG, tmpdir, &pfps, &pcpu) != 0) {
                rc = 1;
                continue;
            }
            char size[16], vf[3][16];
            snprintf(size, sizeof size, "%dx%d", w, h);
            snprintf(vf[0], sizeof vf[0], video ? "%.1f" : "-", vfps);
            snprintf(vf[1], sizeof vf[1], video ? "%.1f" : "-", 1e3 * vcpu);
            snprintf(vf[2], sizeof vf[2], video ? "%.2f" : "-", vfps / target[z]);
            printf("%-9s %-9s %9.1f %9.1f %9.2f %12s %9s %9s %10.1f %9.1f\n", size, render_camera_name(k), fps,
                   1e3 * cpu, fps / target[z], vf[0], vf[1], vf[2], pfps, 1e3 * pcpu);
            if (split) { /* where a frame's time goes: without the HUD, then without the sea too */
                render_scene s2 = sc;
                s2.overlays = 0;
                double f1, c1, f2, c2;
                int bad = bench_case(&b, &s2, ctx, (render_camera_kind)c, w, h, frames, 0, tmpdir, &f1, &c1);
                s2.sea = NULL;
                bad |= bench_case(&b, &s2, ctx, (render_camera_kind)c, w, h, frames, 0, tmpdir, &f2, &c2);
                if (!bad)
                    printf("%-9s %-9s   no HUD %.1f frames/s (%.1f cpu ms), flat sea too %.1f frames/s (%.1f cpu ms)\n",
                           "", "", f1, 1e3 * c1, f2, 1e3 * c2);
            }
        }
        render_destroy(ctx);
    }
    rmdir(tmpdir);
    sim_ship_motion_destroy(m);
    hfm_aircraft_destroy(ac);
    return rc;
}
