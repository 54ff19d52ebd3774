/* pad.c -- the window's inputs as the station's controls: a game
 * controller's sticks and buttons (SDL's game-controller API: axes
 * SDL_CONTROLLER_AXIS_* from -32768 to 32767, up and left negative), the
 * keys of the window, and the pipe of struct input_event that carries them
 * to the station's loop (read there as an evdev device). */
#include "otw.h"

#include <SDL.h>
#include <errno.h>
#include <linux/input.h>
#include <math.h>
#include <string.h>
#include <sys/time.h>
#include <unistd.h>

#define INPUT_MAX 10000 /* a hundredth of a percent */

double otw_pad_pct(int value, double dead_frac, int invert)
{
    double x = value < 0 ? value / 32768.0 : value / 32767.0; /* -1 .. 1 */
    double f = dead_frac > 0.0 && dead_frac < 1.0 ? dead_frac : 0.0, ax = fabs(x);
    if (f > 0.0)
        x = ax <= f ? 0.0 : copysign((ax - f) / (1.0 - f), x);
    double pct = 50.0 + 50.0 * x;
    pct = pct < 0.0 ? 0.0 : pct > 100.0 ? 100.0 : pct;
    return invert ? 100.0 - pct : pct;
}

void otw_pad_map_default(otw_pad_map *m)
{
    memset(m, 0, sizeof *m);
    m->axis[SIM_AXIS_COLLECTIVE] = SDL_CONTROLLER_AXIS_LEFTY;
    m->invert[SIM_AXIS_COLLECTIVE] = 1; /* stick up (negative) = more */
    m->axis[SIM_AXIS_LONG] = SDL_CONTROLLER_AXIS_RIGHTY;
    m->axis[SIM_AXIS_LAT] = SDL_CONTROLLER_AXIS_RIGHTX;
    m->axis[SIM_AXIS_PEDAL] = SDL_CONTROLLER_AXIS_LEFTX;
    m->trim_button = SDL_CONTROLLER_BUTTON_LEFTSHOULDER;
    m->trim_release = SDL_CONTROLLER_BUTTON_RIGHTSHOULDER;
    m->take_over = SDL_CONTROLLER_BUTTON_START;
    m->dead_frac = 0.1;
}

int otw_pad_axis(const otw_pad_map *m, int axis, int value, sim_station_controls *c)
{
    double *dst[SIM_AXES] = {&c->ctl.collective_pct, &c->ctl.long_cyclic_pct, &c->ctl.lat_cyclic_pct,
                             &c->ctl.pedal_pct};
    int hit = 0;
    for (int k = 0; k < SIM_AXES; k++)
        if (m->axis[k] >= 0 && m->axis[k] == axis) {
            *dst[k] = otw_pad_pct(value, m->dead_frac, m->invert[k]);
            hit = 1;
        }
    return hit;
}

int otw_pad_button(const otw_pad_map *m, int button, int down, sim_station_controls *c)
{
    if (button < 0)
        return 0;
    if (button == m->trim_button)
        c->trim_button = down != 0;
    else if (button == m->trim_release)
        c->trim_release = down != 0;
    else if (button == m->take_over)
        c->take_over = down != 0;
    else
        return 0;
    return 1;
}

static void step(double *v, double d)
{
    *v += d;
    *v = *v < 0.0 ? 0.0 : *v > 100.0 ? 100.0 : *v;
}

int otw_keys_feed(int sym, double step_pct, sim_station_controls *c, render_camera_kind *camera)
{
    switch (sym) {
    case SDLK_w: step(&c->ctl.collective_pct, step_pct); return OTW_KEY_MOVED;
    case SDLK_s: step(&c->ctl.collective_pct, -step_pct); return OTW_KEY_MOVED;
    case SDLK_UP: step(&c->ctl.long_cyclic_pct, -step_pct); return OTW_KEY_MOVED; /* forward */
    case SDLK_DOWN: step(&c->ctl.long_cyclic_pct, step_pct); return OTW_KEY_MOVED;
    case SDLK_LEFT: step(&c->ctl.lat_cyclic_pct, -step_pct); return OTW_KEY_MOVED;
    case SDLK_RIGHT: step(&c->ctl.lat_cyclic_pct, step_pct); return OTW_KEY_MOVED;
    case SDLK_a: step(&c->ctl.pedal_pct, -step_pct); return OTW_KEY_MOVED;
    case SDLK_d: step(&c->ctl.pedal_pct, step_pct); return OTW_KEY_MOVED;
    case SDLK_SPACE:
        c->ctl.long_cyclic_pct = c->ctl.lat_cyclic_pct = c->ctl.pedal_pct = 50.0;
        return OTW_KEY_MOVED;
    case SDLK_t: return OTW_KEY_TAKE_OVER;
    case SDLK_c: *camera = (render_camera_kind)(((int)*camera + 1) % RENDER_CAM_COUNT); return OTW_KEY_CAMERA;
    case SDLK_1: case SDLK_2: case SDLK_3: case SDLK_4:
        *camera = (render_camera_kind)(sym - SDLK_1);
        return OTW_KEY_CAMERA;
    case SDLK_q: case SDLK_ESCAPE: return OTW_KEY_QUIT;
    default: return OTW_KEY_NONE;
    }
}

void otw_input_axes(sim_station_axes *a)
{
    static const int code[SIM_AXES] = {ABS_X, ABS_Y, ABS_RX, ABS_RY};
    memset(a, 0, sizeof *a);
    for (int k = 0; k < SIM_AXES; k++)
        a->axis[k] = (sim_station_axis){code[k], 0, 0, INPUT_MAX, 0, 0}; /* spring-centred: force trim */
    a->trim_button_code = BTN_TL;
    a->trim_release_code = BTN_TR;
    a->take_over_code = BTN_START;
}

static void event(struct input_event *e, int type, int code, int value)
{
    memset(e, 0, sizeof *e);
    gettimeofday(&e->time, NULL);
    e->type = (unsigned short)type;
    e->code = (unsigned short)code;
    e->value = value;
}

int otw_input_write(int fd, const sim_station_controls *c)
{
    sim_station_axes a;
    otw_input_axes(&a);
    const double pct[SIM_AXES] = {c->ctl.collective_pct, c->ctl.long_cyclic_pct, c->ctl.lat_cyclic_pct,
                                  c->ctl.pedal_pct};
    struct input_event ev[SIM_AXES + 4];
    int n = 0;
    for (int k = 0; k < SIM_AXES; k++) {
        double v = pct[k] < 0.0 ? 0.0 : pct[k] > 100.0 ? 100.0 : pct[k];
        event(&ev[n++], EV_ABS, a.axis[k].code, (int)lround(v * (INPUT_MAX / 100.0)));
    }
    event(&ev[n++], EV_KEY, BTN_TL, c->trim_button != 0);
    event(&ev[n++], EV_KEY, BTN_TR, c->trim_release != 0);
    event(&ev[n++], EV_KEY, BTN_START, c->take_over != 0);
    event(&ev[n++], EV_SYN, SYN_REPORT, 0);
    /* one write of whole records (under PIPE_BUF: never split) */
    ssize_t w;
    do
        w = write(fd, ev, (size_t)n * sizeof ev[0]);
    while (w < 0 && errno == EINTR);
    return w == (ssize_t)((size_t)n * sizeof ev[0]) ? 0 : -1;
}
