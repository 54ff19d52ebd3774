/* cmd_render.c -- `disim render SCENARIO -o VIEW.png [--eye-S X,Y,Z]
 * [--target-S X,Y,Z] [--size WxH] [--fov-deg F]`: an off-screen deck view
 * of the scenario's ship with the helicopter's hover station marked. */
#include "cmds.h"
#include "render.h"
#include "sim.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* One side of --size: digits only (no sign, no blanks), within what
 * render_create accepts; sscanf's %d was undefined on overflow and let
 * 99999999999 through as -1. */
static int parse_side(const char *s, const char **end, int *out)
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

static int parse3(const char *flag, const char *s, double v[3])
{
    if (core_parse_vec3(s, v, NULL)) {
        fprintf(stderr, "disim render: %s '%s': expected X,Y,Z in metres (ship frame)\n", flag, s);
        return -1;
    }
    return 0;
}

int cmd_render(int argc, char **argv)
{
    const char *scen = NULL, *out = NULL;
    int w = 1280, h = 720, have_eye = 0, have_target = 0;
    render_camera cam = {{0, 0, 0}, {0, 0, 0}, 50.0};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int takes = !strcmp(a, "-o") || !strcmp(a, "--eye-S") || !strcmp(a, "--target-S") ||
                    !strcmp(a, "--size") || !strcmp(a, "--fov-deg");
        if (takes && !v) {
            fprintf(stderr, "disim render: %s: expected a value\n", a);
            return 2;
        }
        if (!strcmp(a, "-o"))
            out = v;
        else if (!strcmp(a, "--eye-S")) {
            if (parse3(a, v, cam.eye_S_m))
                return 2;
            have_eye = 1;
        } else if (!strcmp(a, "--target-S")) {
            if (parse3(a, v, cam.target_S_m))
                return 2;
            have_target = 1;
        } else if (!strcmp(a, "--size")) {
            const char *e;
            if (parse_side(v, &e, &w) || *e != 'x' || parse_side(e + 1, &e, &h) || *e) {
                fprintf(stderr,
                        "disim render: --size '%s': expected WIDTHxHEIGHT, e.g. 1280x720, each %d to %d "
                        "pixels\n",
                        v, RENDER_SIZE_MIN, RENDER_SIZE_MAX);
                return 2;
            }
        } else if (!strcmp(a, "--fov-deg")) {
            char *end;
            cam.fov_y_deg = strtod(v, &end);
            if (*end || !(cam.fov_y_deg > 1 && cam.fov_y_deg < 170)) {
                fprintf(stderr, "disim render: --fov-deg '%s': expected degrees, 1 to 170\n", v);
                return 2;
            }
        } else if (a[0] == '-') {
            fprintf(stderr, "disim render: unknown flag '%s'\n", a);
            return 2;
        } else if (!scen) {
            scen = a;
            continue;
        } else {
            fprintf(stderr, "disim render: unexpected argument '%s'\n", a);
            return 2;
        }
        i++;
    }
    if (!scen || !out) {
        fprintf(stderr, "usage: disim render SCENARIO -o VIEW.png [--eye-S X,Y,Z] [--target-S X,Y,Z] "
                        "[--size WxH] [--fov-deg F]\n");
        return 2;
    }
    sim_scenario *sc = malloc(sizeof *sc);
    core_err err = {{0}};
    if (!sc || sim_scenario_load(scen, sc, &err)) {
        fprintf(stderr, "disim render: %s\n", err.msg);
        free(sc);
        return 1;
    }
    if (!have_eye) { /* the starboard quarter, above and astern of the deck */
        cam.eye_S_m[0] = sc->ship.deck_x0_m - 45.0;
        cam.eye_S_m[1] = 25.0;
        cam.eye_S_m[2] = -22.0;
    }
    if (!have_target) {
        cam.target_S_m[0] = sc->ship.deck_x1_m;
        cam.target_S_m[1] = 0.0;
        cam.target_S_m[2] = -4.0;
    }
    int rc = 1;
    uint8_t *img = malloc((size_t)4 * w * h);
    render_ctx *r = render_create(w, h, &err);
    if (img && r && render_deck_view(r, &sc->ship, &cam, sc->station_S_m, img, &err) == 0 &&
        render_write_png(out, w, h, img, &err) == 0) {
        printf("disim render: wrote %s (%dx%d, %s)\n", out, w, h, sc->ship.name);
        rc = 0;
    } else {
        fprintf(stderr, "disim render: %s\n", err.msg[0] ? err.msg : "out of memory");
    }
    render_destroy(r);
    free(img);
    free(sc);
    return rc;
}
