/* test_otw.c -- the view's input mapping, with no device and no window
 * (otw/pad.c):
 *  - a game controller's stick (SDL: -32768 to 32767) in percent of
 *    travel: the stops, the centre, the dead band reading 50 % and the
 *    travel stretched beyond it without a step, inversion;
 *  - the helicopter layout: which stick moves which control and which way,
 *    the shoulder buttons the force trim, START the take-over, unmapped
 *    axes and buttons ignored;
 *  - the window's keys: steps, clamps, centring, take-over, cameras, quit;
 *  - the input pipe: controls written as input events and read back by the
 *    station's evdev reader (sim_station_evdev_wrap) to within 0.01 %. */
#include "check.h"
#include "otw.h"

#include <SDL.h>
#include <string.h>
#include <unistd.h>

static void test_pct(void)
{
    CHECK_NEAR(otw_pad_pct(-32768, 0.1, 0), 0.0, 1e-12);
    CHECK_NEAR(otw_pad_pct(32767, 0.1, 0), 100.0, 1e-12);
    CHECK_NEAR(otw_pad_pct(0, 0.1, 0), 50.0, 1e-12);
    CHECK_NEAR(otw_pad_pct(-32768, 0.1, 1), 100.0, 1e-12);
    /* inside the dead band: the centre */
    CHECK_NEAR(otw_pad_pct(3000, 0.1, 0), 50.0, 1e-12);
    CHECK_NEAR(otw_pad_pct(-3276, 0.1, 0), 50.0, 1e-12);
    /* at its edge no step, beyond it stretched: half way from the edge to the stop reads 75 % */
    CHECK_NEAR(otw_pad_pct(3277, 0.1, 0), 50.0, 0.01);
    CHECK_NEAR(otw_pad_pct((int)(0.55 * 32767), 0.1, 0), 75.0, 0.01);
    CHECK_NEAR(otw_pad_pct((int)(-0.55 * 32768), 0.1, 0), 25.0, 0.01);
    /* no dead band: linear */
    CHECK_NEAR(otw_pad_pct(16384, 0.0, 0), 75.0, 0.01);
    /* monotonic over the whole travel */
    double last = -1.0;
    int mono = 1;
    for (int v = -32768; v <= 32767; v += 97) {
        double p = otw_pad_pct(v, 0.1, 0);
        mono &= p >= last && p >= 0.0 && p <= 100.0;
        last = p;
    }
    CHECK(mono);
}

static void test_layout(void)
{
    otw_pad_map m;
    otw_pad_map_default(&m);
    sim_station_controls c;
    sim_station_controls_centre(&c);
    /* left stick up: more collective */
    CHECK(otw_pad_axis(&m, SDL_CONTROLLER_AXIS_LEFTY, -32768, &c) == 1);
    CHECK_NEAR(c.ctl.collective_pct, 100.0, 1e-9);
    /* right stick forward (up): long cyclic 0 % (full forward) */
    CHECK(otw_pad_axis(&m, SDL_CONTROLLER_AXIS_RIGHTY, -32768, &c) == 1);
    CHECK_NEAR(c.ctl.long_cyclic_pct, 0.0, 1e-9);
    /* right stick left: lat cyclic 0 % (full left) */
    CHECK(otw_pad_axis(&m, SDL_CONTROLLER_AXIS_RIGHTX, -32768, &c) == 1);
    CHECK_NEAR(c.ctl.lat_cyclic_pct, 0.0, 1e-9);
    /* left stick right: right pedal */
    CHECK(otw_pad_axis(&m, SDL_CONTROLLER_AXIS_LEFTX, 32767, &c) == 1);
    CHECK_NEAR(c.ctl.pedal_pct, 100.0, 1e-9);
    /* the triggers are not mapped */
    sim_station_controls before = c;
    CHECK(otw_pad_axis(&m, SDL_CONTROLLER_AXIS_TRIGGERLEFT, 32767, &c) == 0);
    CHECK(memcmp(&before, &c, sizeof c) == 0);
    CHECK(otw_pad_button(&m, SDL_CONTROLLER_BUTTON_LEFTSHOULDER, 1, &c) == 1 && c.trim_button == 1);
    CHECK(otw_pad_button(&m, SDL_CONTROLLER_BUTTON_LEFTSHOULDER, 0, &c) == 1 && c.trim_button == 0);
    CHECK(otw_pad_button(&m, SDL_CONTROLLER_BUTTON_RIGHTSHOULDER, 1, &c) == 1 && c.trim_release == 1);
    CHECK(otw_pad_button(&m, SDL_CONTROLLER_BUTTON_START, 1, &c) == 1 && c.take_over == 1);
    CHECK(otw_pad_button(&m, SDL_CONTROLLER_BUTTON_A, 1, &c) == 0);
}

static void test_keys(void)
{
    sim_station_controls c;
    sim_station_controls_centre(&c);
    render_camera_kind cam = RENDER_CAM_PILOT;
    CHECK(otw_keys_feed(SDLK_w, 2.0, &c, &cam) == OTW_KEY_MOVED);
    CHECK_NEAR(c.ctl.collective_pct, 52.0, 1e-12);
    CHECK(otw_keys_feed(SDLK_UP, 2.0, &c, &cam) == OTW_KEY_MOVED);
    CHECK_NEAR(c.ctl.long_cyclic_pct, 48.0, 1e-12); /* forward */
    CHECK(otw_keys_feed(SDLK_LEFT, 2.0, &c, &cam) == OTW_KEY_MOVED);
    CHECK_NEAR(c.ctl.lat_cyclic_pct, 48.0, 1e-12);
    CHECK(otw_keys_feed(SDLK_d, 2.0, &c, &cam) == OTW_KEY_MOVED);
    CHECK_NEAR(c.ctl.pedal_pct, 52.0, 1e-12);
    for (int i = 0; i < 40; i++)
        otw_keys_feed(SDLK_s, 2.0, &c, &cam);
    CHECK_NEAR(c.ctl.collective_pct, 0.0, 1e-12); /* clamped */
    CHECK(otw_keys_feed(SDLK_SPACE, 2.0, &c, &cam) == OTW_KEY_MOVED);
    CHECK(c.ctl.long_cyclic_pct == 50.0 && c.ctl.lat_cyclic_pct == 50.0 && c.ctl.pedal_pct == 50.0 &&
          c.ctl.collective_pct == 0.0); /* the lever stays */
    CHECK(otw_keys_feed(SDLK_t, 2.0, &c, &cam) == OTW_KEY_TAKE_OVER);
    CHECK(otw_keys_feed(SDLK_c, 2.0, &c, &cam) == OTW_KEY_CAMERA && cam == RENDER_CAM_DECK);
    CHECK(otw_keys_feed(SDLK_4, 2.0, &c, &cam) == OTW_KEY_CAMERA && cam == RENDER_CAM_OVERHEAD);
    CHECK(otw_keys_feed(SDLK_c, 2.0, &c, &cam) == OTW_KEY_CAMERA && cam == RENDER_CAM_PILOT);
    CHECK(otw_keys_feed(SDLK_q, 2.0, &c, &cam) == OTW_KEY_QUIT);
    CHECK(otw_keys_feed(SDLK_ESCAPE, 2.0, &c, &cam) == OTW_KEY_QUIT);
    CHECK(otw_keys_feed(SDLK_z, 2.0, &c, &cam) == OTW_KEY_NONE);
}

static void test_pipe(void)
{
    int fd[2];
    CHECK(pipe(fd) == 0);
    sim_station_axes a;
    otw_input_axes(&a);
    core_err err;
    sim_station_evdev *d = sim_station_evdev_wrap(fd[0], &a, &err);
    CHECK(d != NULL);
    if (!d)
        return;
    sim_station_controls c, got;
    sim_station_controls_centre(&c);
    sim_station_controls_centre(&got);
    c.ctl.collective_pct = 63.27;
    c.ctl.long_cyclic_pct = 0.0;
    c.ctl.lat_cyclic_pct = 100.0;
    c.ctl.pedal_pct = 41.005;
    c.trim_button = 1;
    c.take_over = 1;
    CHECK(otw_input_write(fd[1], &c) == 0);
    CHECK(sim_station_evdev_read(d, &got, &err) == 0);
    CHECK_NEAR(got.ctl.collective_pct, 63.27, 0.01);
    CHECK_NEAR(got.ctl.long_cyclic_pct, 0.0, 1e-9);
    CHECK_NEAR(got.ctl.lat_cyclic_pct, 100.0, 1e-9);
    CHECK_NEAR(got.ctl.pedal_pct, 41.005, 0.01);
    CHECK(got.trim_button == 1 && got.trim_release == 0 && got.take_over == 1);
    c.take_over = 0;
    c.trim_button = 0;
    CHECK(otw_input_write(fd[1], &c) == 0);
    CHECK(sim_station_evdev_read(d, &got, &err) == 0);
    CHECK(got.take_over == 0 && got.trim_button == 0);
    /* the window gone: the station's reader says so */
    close(fd[1]);
    CHECK(sim_station_evdev_read(d, &got, &err) < 0);
    sim_station_evdev_destroy(d);
}

int main(void)
{
    test_pct();
    test_layout();
    test_keys();
    test_pipe();
    return check_done("test_otw");
}
