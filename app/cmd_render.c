/* cmd_render.c -- `disim render`: a recorded run as frames and video, or a
 * scenario's deck as one still image.
 *
 *   disim render LOG -o DIR [--camera pilot|deck|chase|overhead|all[,...]]
 *                [--fps 30] [--size 1280x720] [--overlay hud,airwake]
 *                [--from S] [--to S] [--frames on|off] [--video on|off]
 *                [--scenario S.ini [--seed N]] [--field F.h5 | --db DIR]
 *   disim render SCENARIO.ini -o VIEW.png [--eye-S X,Y,Z] [--target-S X,Y,Z]
 *                [--size WxH] [--fov-deg F]
 *
 * A log (disim fly --log) is drawn from its states (sim_log_state_at)
 * in the scene its run_info_t names (app/scene.c): DIR/CAMERA_NNNNNN.png
 * and DIR/CAMERA.mp4 per camera (ffmpeg), each written to a temporary
 * name and renamed. A progress line on a terminal, none in a log. */
#include "cmds.h"
#include "render.h"
#include "scene.h"
#include "sim.h"
#ifdef DISIM_HAVE_AIRWAKED
#include "awdb.h"
#endif

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int parse_size(const char *v, int *w, int *h)
{
    core_err err = {0};
    if (render_size_parse(v, w, h, &err) != 0) {
        fprintf(stderr, "disim render: --size %s\n", err.msg);
        return -1;
    }
    return 0;
}

static int parse3(const char *flag, const char *s, double v[3])
{
    if (core_parse_vec3(s, v, NULL)) {
        fprintf(stderr, "disim render: %s '%s': expected X,Y,Z in metres (ship frame)\n", flag, s);
        return -1;
    }
    return 0;
}

static int on_off(const char *flag, const char *v, int *out)
{
    if (!strcmp(v, "on") || !strcmp(v, "off")) {
        *out = !strcmp(v, "on");
        return 0;
    }
    fprintf(stderr, "disim render: %s '%s': expected on or off\n", flag, v);
    return -1;
}

/* "deck", "pilot,chase", "all" into camera bits. */
static int parse_cameras(const char *list, unsigned *bits)
{
    *bits = 0;
    char buf[256];
    snprintf(buf, sizeof buf, "%s", list);
    for (char *tok = strtok(buf, ","); tok; tok = strtok(NULL, ",")) {
        render_camera_kind k;
        core_err err = {0};
        if (!strcmp(tok, "all"))
            *bits |= (1u << RENDER_CAM_COUNT) - 1u;
        else if (render_camera_parse(tok, &k, &err) == 0)
            *bits |= 1u << k;
        else {
            fprintf(stderr, "disim render: --camera '%s': %s (or all)\n", list, err.msg);
            return -1;
        }
    }
    if (!*bits) {
        fprintf(stderr, "disim render: --camera '%s': expected pilot, deck, chase, overhead or all\n", list);
        return -1;
    }
    return 0;
}

typedef struct render_args {
    const char *in, *out, *scenario, *field, *db;
    int w, h, frames, video, size_set;
    int log_flags, still_flags; /* flags given that are for a log, for the still image */
    double fps, from_s, to_s, seed;
    unsigned cameras, overlays;
    /* the still image */
    int have_eye, have_target;
    render_camera cam;
} render_args;

static int is_ini(const char *p)
{
    size_t n = strlen(p);
    return n > 4 && !strcmp(p + n - 4, ".ini");
}

/* ------------------------------------------------------- the still image */
static int render_still(const render_args *a)
{
    sim_scenario *sc = malloc(sizeof *sc);
    core_err err = {0};
    if (!sc || sim_scenario_load(a->in, sc, &err)) {
        fprintf(stderr, "disim render: %s\n", sc ? err.msg : "out of memory");
        free(sc);
        return 1;
    }
    /* the image's target before drawing: a regular file or new, no input */
    const char *inputs[] = {a->in, sc->aircraft_path, sc->ship_path};
    int same = 0;
    for (int i = 0; i < 3; i++)
        same |= core_path_same(a->out, inputs[i]);
    if (core_output_check(a->out, &err) != 0 || (same && core_err_set(&err, -1, "%s: an input of this run", a->out))) {
        fprintf(stderr, "disim render: -o %s\n", err.msg);
        free(sc);
        return 1;
    }
    render_camera cam = a->cam;
    if (!a->have_eye) { /* the starboard quarter, above and astern of the deck */
        cam.eye_S_m[0] = sc->ship.deck_x0_m - 45.0;
        cam.eye_S_m[1] = 25.0;
        cam.eye_S_m[2] = -22.0;
    }
    if (!a->have_target) {
        cam.target_S_m[0] = sc->ship.deck_x1_m;
        cam.target_S_m[1] = 0.0;
        cam.target_S_m[2] = -4.0;
    }
    int rc = 1;
    uint8_t *img = malloc((size_t)4 * a->w * a->h);
    render_ctx *r = render_create(a->w, a->h, &err);
    if (img && r && render_deck_view(r, &sc->ship, &cam, sc->station_S_m, img, &err) == 0 &&
        render_write_png(a->out, a->w, a->h, img, &err) == 0) {
        printf("disim render: wrote %s (%dx%d, %s)\n", a->out, a->w, a->h, sc->ship.name);
        rc = 0;
    } else {
        fprintf(stderr, "disim render: %s\n", err.msg[0] ? err.msg : "out of memory");
    }
    render_destroy(r);
    free(img);
    free(sc);
    return rc;
}

/* ------------------------------------------------------------- a log */
/* The run's information: the log's run_info_t, or --scenario's. */
static int run_info_of(const render_args *a, const sim_log *L, sim_run_info *ri, core_err *err)
{
    if (!a->scenario) {
        if (sim_log_run_info(L, ri) == 0)
            return 0;
        return core_err_set(err, -1,
                            "%s: no run_info_t in the log (written by a disim before run information was "
                            "logged): give the scenario it was flown from, --scenario S.ini [--seed N]",
                            a->in);
    }
    sim_scenario *sc = malloc(sizeof *sc);
    if (!sc)
        return core_err_set(err, -1, "out of memory");
    if (sim_scenario_load(a->scenario, sc, err) != 0) {
        free(sc);
        return -1;
    }
    sim_world_overrides ov; /* the scenario's own keys, the run's seed */
    sim_world_overrides_default(&ov);
    ov.seed = (unsigned long long)a->seed;
    sim_world_run_info(sc, &ov, ri);
    ri->state_rate_hz = 50.0;
    free(sc);
    return 0;
}

/* The airwake overlay's field: --field, else the run's ship-only field in
 * the database (--db, default out/airwake-db), never built from here. */
static int overlay_field(const render_args *a, app_scene *s, core_err *err)
{
    cfd_field *f = NULL;
    if (a->field) {
        if (!(f = cfd_field_load(a->field, err)))
            return -1;
    } else {
#ifdef DISIM_HAVE_AIRWAKED
        sim_scenario *sc = malloc(sizeof *sc);
        if (!sc)
            return core_err_set(err, -1, "out of memory");
        if (sim_scenario_load(s->run.info.scenario_path, sc, err) != 0) {
            free(sc);
            return -1;
        }
        const char *dbdir = a->db ? a->db : "out/airwake-db";
        awdb *db = awdb_open(dbdir, NULL, err);
        if (!db) {
            free(sc);
            return -1;
        }
        awdb_key k;
        awdb_key_ship_only(&k, sc->ship.name, sc->aircraft_name, AWDB_SHIP_ONLY_REF_MPS, s->run.info.wod_dir_rad,
                           sc->grid);
        char path[1024];
        int rc = awdb_key_canon(&k, err);
        if (rc == 0 && awdb_query(db, &k, path, sizeof path) != AWDB_READY)
            rc = core_err_set(err, -1,
                              "--overlay airwake: no ship-only field of %s for %.0f deg in %s: build it (disim "
                              "airwaked) or give --field F.h5",
                              sc->ship.name, s->run.info.wod_dir_rad * CORE_RAD_TO_DEG, dbdir);
        awdb_close(db);
        free(sc);
        if (rc != 0 || !(f = cfd_field_load(path, err)))
            return -1;
#else
        return core_err_set(err, -1, "--overlay airwake: give the field, --field F.h5");
#endif
    }
    if (app_scene_set_field(s, f, err) != 0) {
        cfd_field_destroy(f);
        return -1;
    }
    return 0;
}

/* The progress line on a terminal: camera, percent, rate, time left. */
static void progress(int tty, const char *cam, long done, long total, double t0_wall)
{
    if (!tty)
        return;
    double el = core_monotonic_s() - t0_wall, rate = el > 0.0 ? done / el : 0.0;
    double left = rate > 0.0 ? (total - done) / rate : 0.0;
    fprintf(stderr, "\r\033[Krender: %s %3.0f %% (%ld/%ld frames), %.1f frames/s, %.0f s left", cam,
            100.0 * done / (total > 0 ? total : 1), done, total, rate, left);
    fflush(stderr);
}

/* One camera's frames and video. 0, or < 0 with err (nothing of the
 * video left; the PNGs written so far stay, each whole). */
static int render_camera_run(const render_args *a, app_scene *s, const sim_log *L, render_camera_kind cam,
                             render_ctx *rc, uint8_t *img, double t0, long n, int tty, core_err *err)
{
    const char *name = render_camera_name(cam);
    size_t plen = strlen(a->out) + 64;
    char *path = malloc(plen);
    if (!path)
        return core_err_set(err, -1, "out of memory");
    render_video *v = NULL;
    int r = -1;
    if (a->video) {
        snprintf(path, plen, "%s/%s.mp4", a->out, name);
        if (!(v = render_video_open(path, a->w, a->h, a->fps, err)))
            goto out;
    }
    double start = core_monotonic_s(), last = -1.0;
    for (long i = 0; i < n; i++) {
        sim_log_state ls;
        render_state st;
        render_view view;
        sim_log_state_at(L, t0 + i / a->fps, &ls);
        app_render_state_from_log(s, &ls, &st);
        if (render_camera_place(cam, &s->scene, &st, &view, err) != 0 ||
            render_frame(rc, &s->scene, &st, &view, img, err) != 0)
            goto out;
        if (a->frames) {
            snprintf(path, plen, "%s/%s_%06ld.png", a->out, name, i);
            if (render_write_png(path, a->w, a->h, img, err) != 0)
                goto out;
        }
        if (v && render_video_frame(v, img, err) != 0)
            goto out;
        double now = core_monotonic_s();
        if (now - last > 0.5 || i + 1 == n) {
            progress(tty, name, i + 1, n, start);
            last = now;
        }
    }
    if (v) {
        render_video *vv = v;
        v = NULL;
        if (render_video_close(vv, err) != 0)
            goto out;
    }
    r = 0;
out:
    if (tty)
        fprintf(stderr, "\r\033[K");
    if (v)
        render_video_abort(v);
    free(path);
    return r;
}

static int render_log(const render_args *a)
{
    core_err err = {0};
    int tty = isatty(2);
    app_log al = {"render", tty};
    core_log log = {app_log_stderr, &al, CORE_LOG_WARN};
    app_scene s;
    memset(&s, 0, sizeof s);
    render_ctx *rc = NULL;
    uint8_t *img = NULL;
    int ret = 1;
    if (core_dir_check(a->out, &err) != 0) { /* before the log is read and the frames drawn */
        fprintf(stderr, "disim render: -o %s\n", err.msg);
        return 1;
    }
    sim_log *L = sim_log_load(a->in, &err);
    sim_run_info ri;
    if (!L || run_info_of(a, L, &ri, &err) != 0 || app_scene_open(&s, &ri, a->overlays, &log, &err) != 0)
        goto fail;
    if ((a->overlays & RENDER_OVERLAY_AIRWAKE) && overlay_field(a, &s, &err) != 0)
        goto fail;
    /* the sea drawn only where it is the one the ship moved in */
    double off = app_scene_check_log(&s, L);
    if (!(off < 0.05)) {
        fprintf(stderr,
                "disim render: warning: the log's ship moves %.3g m off the seaway rebuilt from %s (seed %llu, sea "
                "state %d): the sea is drawn flat\n",
                off, a->scenario ? a->scenario : "its run_info_t", ri.seed, ri.sea.state);
        s.scene.sea = NULL;
    }
    sim_log_summary info;
    sim_log_info(L, &info);
    double t0 = fmax(info.t0_s, a->from_s), t1 = fmin(info.t1_s, a->to_s);
    if (!(t1 >= t0)) {
        core_err_set(&err, -1, "--from %g / --to %g: outside the log's %.2f to %.2f s", a->from_s, a->to_s, info.t0_s,
                     info.t1_s);
        goto fail;
    }
    long n = (long)floor((t1 - t0) * a->fps + 1e-9) + 1;
    if (a->video && !render_video_available()) {
        core_err_set(&err, -1, "--video on: no ffmpeg with H.264 on PATH (install ffmpeg, or --video off)");
        goto fail;
    }
    if (core_mkdir_p(a->out, &err) != 0)
        goto fail;
    if (!(img = malloc((size_t)4 * a->w * a->h))) {
        core_err_set(&err, -1, "out of memory");
        goto fail;
    }
    if (!(rc = render_create(a->w, a->h, &err)))
        goto fail;
    fprintf(stderr, "render: %s, %.2f to %.2f s, %ld frames at %g frames/s, %dx%d, into %s\n", s.run.name, t0, t1, n,
            a->fps, a->w, a->h, a->out);
    double wall0 = core_monotonic_s();
    int ncam = 0;
    for (int c = 0; c < RENDER_CAM_COUNT; c++) {
        if (!(a->cameras & (1u << c)))
            continue;
        if (render_camera_run(a, &s, L, (render_camera_kind)c, rc, img, t0, n, tty, &err) != 0)
            goto fail;
        printf("disim render: %s: %ld frames%s%s%s%s\n", render_camera_name((render_camera_kind)c), n,
               a->frames ? " as " : "", a->frames ? a->out : "", a->frames ? "/*.png" : "",
               a->video ? ", and a video" : "");
        if (a->video)
            printf("disim render: wrote %s/%s.mp4\n", a->out, render_camera_name((render_camera_kind)c));
        ncam++;
    }
    double wall = core_monotonic_s() - wall0;
    fprintf(stderr, "render: %ld frames in %.1f s (%.1f frames/s)\n", n * ncam, wall, wall > 0 ? n * ncam / wall : 0);
    ret = 0;
    goto done;
fail:
    fprintf(stderr, "disim render: %s\n", err.msg[0] ? err.msg : "failed");
done:
    render_destroy(rc);
    free(img);
    app_scene_close(&s);
    sim_log_destroy(L);
    return ret;
}

static void usage(void)
{
    fprintf(stderr,
            "usage: disim render LOG -o DIR [--camera pilot|deck|chase|overhead|all[,...]] [--fps F]\n"
            "                    [--size WxH] [--overlay hud,airwake] [--from S] [--to S] [--frames on|off]\n"
            "                    [--video on|off] [--scenario S.ini [--seed N]] [--field F.h5 | --db DIR]\n"
            "       disim render SCENARIO.ini -o VIEW.png [--eye-S X,Y,Z] [--target-S X,Y,Z] [--size WxH]\n"
            "                    [--fov-deg F]\n");
}

/* One flag f and its value v into a (counted as a log's or the still
 * image's): 0, or 2 after saying what was expected. */
static int render_flag(render_args *a, const char *f, const char *v)
{
    core_err err = {0};
    int bad = 0;
    if (!strcmp(f, "-o"))
        a->out = v;
    else if (!strcmp(f, "--size")) {
        bad = parse_size(v, &a->w, &a->h) != 0;
        a->size_set = 1;
    } else if (!strcmp(f, "--eye-S") || !strcmp(f, "--target-S")) {
        int eye = f[2] == 'e';
        bad = parse3(f, v, eye ? a->cam.eye_S_m : a->cam.target_S_m) != 0;
        *(eye ? &a->have_eye : &a->have_target) = 1;
        a->still_flags++;
    } else if (!strcmp(f, "--fov-deg")) {
        bad = app_parse_double("disim render", f, v, 1.0 + 1e-9, 170.0 - 1e-9, &a->cam.fov_y_deg) != 0;
        a->still_flags++;
    } else {
        a->log_flags++;
        if (!strcmp(f, "--camera"))
            bad = parse_cameras(v, &a->cameras) != 0;
        else if (!strcmp(f, "--fps"))
            bad = app_parse_double("disim render", f, v, 0.1, 240.0, &a->fps) != 0;
        else if (!strcmp(f, "--overlay") && render_overlays_parse(v, &a->overlays, &err) != 0) {
            fprintf(stderr, "disim render: --overlay '%s': %s\n", v, err.msg);
            bad = 1;
        } else if (!strcmp(f, "--from") || !strcmp(f, "--to"))
            bad = app_parse_double("disim render", f, v, -1e9, 1e9, f[2] == 'f' ? &a->from_s : &a->to_s) != 0;
        else if (!strcmp(f, "--frames") || !strcmp(f, "--video"))
            bad = on_off(f, v, f[2] == 'f' ? &a->frames : &a->video) != 0;
        else if (!strcmp(f, "--seed") &&
                 (app_parse_double("disim render", f, v, 0.0, 9007199254740992.0, &a->seed) || a->seed != floor(a->seed))) {
            fprintf(stderr, "disim render: --seed: expected a whole number\n");
            bad = 1;
        } else if (!strcmp(f, "--scenario"))
            a->scenario = v;
        else if (!strcmp(f, "--field"))
            a->field = v;
        else if (!strcmp(f, "--db"))
            a->db = v;
    }
    return bad ? 2 : 0;
}

static int render_parse(int argc, char **argv, render_args *a)
{
    memset(a, 0, sizeof *a);
    a->w = 1280, a->h = 720, a->fps = 30.0, a->frames = 1, a->video = -1, a->from_s = -INFINITY, a->to_s = INFINITY;
    a->seed = 1.0;
    a->cameras = 1u << RENDER_CAM_DECK;
    a->cam.fov_y_deg = 50.0;
    static const char *const takes[] = {"-o", "--eye-S", "--target-S", "--size", "--fov-deg", "--camera",
                                        "--fps", "--overlay", "--from", "--to", "--frames", "--video",
                                        "--scenario", "--seed", "--field", "--db", NULL};
    for (int i = 1; i < argc; i++) {
        const char *f = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int t = 0;
        for (int k = 0; takes[k]; k++)
            t |= !strcmp(f, takes[k]);
        if (t && !v) {
            fprintf(stderr, "disim render: %s: expected a value\n", f);
            return 2;
        }
        if (t) {
            if (render_flag(a, f, v) != 0)
                return 2;
            i++;
        } else if (f[0] == '-') {
            fprintf(stderr, "disim render: unknown flag '%s'\n", f);
            usage();
            return 2;
        } else if (!a->in)
            a->in = f;
        else {
            fprintf(stderr, "disim render: unexpected argument '%s'\n", f);
            return 2;
        }
    }
    if (!a->in || !a->out) {
        usage();
        return 2;
    }
    return 0;
}

/* A log's flags together: 0, or 2 after saying what does not go. */
static int render_check(render_args *a)
{
    if (a->still_flags) {
        fprintf(stderr, "disim render: --eye-S, --target-S and --fov-deg are for a scenario's still image; a log is "
                        "drawn from its cameras (--camera)\n");
        return 2;
    }
    if (a->seed != 1.0 && !a->scenario) {
        fprintf(stderr, "disim render: --seed: only with --scenario (a log's run_info_t has its seed)\n");
        return 2;
    }
    if (a->field && a->db) {
        fprintf(stderr, "disim render: --field and --db: give one\n");
        return 2;
    }
    if ((a->field || a->db) && !(a->overlays & RENDER_OVERLAY_AIRWAKE)) {
        fprintf(stderr, "disim render: --field / --db: only with --overlay airwake\n");
        return 2;
    }
    if (a->video < 0)
        a->video = render_video_available();
    if (!a->frames && !a->video) {
        fprintf(stderr, "disim render: --frames off and --video off: nothing to write\n");
        return 2;
    }
    if ((a->w % 2 || a->h % 2) && a->video)
        fprintf(stderr, "disim render: note: %dx%d is odd: the video is padded to even sides\n", a->w, a->h);
    return 0;
}

int cmd_render(int argc, char **argv)
{
    render_args a;
    int rc = render_parse(argc, argv, &a);
    if (rc)
        return rc;
    if (is_ini(a.in)) {
        if (a.log_flags) {
            fprintf(stderr, "disim render: %s is a scenario: --camera, --fps, --overlay, --from, --to, --frames, "
                            "--video, --scenario, --seed, --field and --db are for a log (disim fly --log)\n",
                    a.in);
            return 2;
        }
        return render_still(&a);
    }
    return (rc = render_check(&a)) ? rc : render_log(&a);
}
