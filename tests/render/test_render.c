/* test_render.c -- off-screen deck views: sky above, sea below, the deck at
 * the look-at point, starboard on the right, a PNG written atomically, and
 * bad sizes refused. */
#include "check.h"
#include "render.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

enum { W = 320, H = 200 };

static const uint8_t *px(const uint8_t *img, int x, int y) { return img + 4 * ((size_t)y * W + x); }

static int is_orange(const uint8_t *p) { return p[0] > 200 && p[1] > 100 && p[1] < 180 && p[2] < 60; }

int main(void)
{
    core_ship ship;
    core_err err = {{0}};
    CHECK(core_ship_load("scenarios/ships/sfs2.ini", &ship, &err) == 0);
    render_ctx *rc = render_create(W, H, &err);
    CHECK(rc != NULL);
    if (!rc)
        return check_done("test_render");
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
    /* The deck's dark grey (0.30, 0.31, 0.32) at the look-at point. */
    CHECK(abs(centre[0] - 77) < 12 && abs(centre[1] - 79) < 12 && abs(centre[2] - 82) < 12);
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
    return check_done("test_render");
}
