/* cmd_station.c -- `disim station`: the reference pilot station. It reads
 * the pilot's controls from a joystick or gamepad (evdev), the keyboard of
 * a terminal or a script, publishes them as pilot_input_t on
 * DISIM_PILOT_INPUT (sim_station_run: 50 Hz on absolute deadlines) and
 * shows what the flight loop sends back. This file parses the flags, puts
 * the terminal in raw mode for the keyboard (and gives it back on every
 * way out: normal exit, SIGINT / SIGTERM / SIGHUP / SIGQUIT, and the fatal
 * signals, whose handler restores it before the default action) and writes
 * the display. With --view the out-the-window view (otw/) runs beside the
 * station: its window on this thread, the station's loop in a thread of
 * its own, and the window's keys and game controllers as the station's
 * source unless another is chosen. */
#include "cmds.h"
#include "disim_lcm.h"
#include "render.h"
#include "sim.h"
#ifdef DISIM_HAVE_OTW
#include "otw.h"
#endif

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <unistd.h>

static volatile sig_atomic_t station_stop = 0;

/* the terminal as it was, for the handlers (set before they are installed) */
static struct termios tty_saved;
static volatile sig_atomic_t tty_raw = 0, tty_display = 0;

static void tty_restore(void)
{
    if (tty_raw) {
        tcsetattr(STDIN_FILENO, TCSAFLUSH, &tty_saved);
        tty_raw = 0;
    }
    if (tty_display) {
        static const char show_cursor[] = "\033[?25h";
        if (write(STDOUT_FILENO, show_cursor, sizeof show_cursor - 1) < 0) {
            /* nothing more to do on the way out */
        }
        tty_display = 0;
    }
}

static void on_stop_signal(int sig)
{
    (void)sig;
    station_stop = 1;
}

/* A crash must not leave the user's terminal without echo: restore it
 * (tcsetattr and write are async-signal-safe), then the default action. */
static void on_fatal_signal(int sig)
{
    tty_restore();
    signal(sig, SIG_DFL);
    raise(sig);
}

static void usage_station(FILE *f)
{
    fprintf(f,
            "usage: disim station [--keyboard | --device /dev/input/eventN | --script FILE.csv [--script-absolute]]\n"
            "                     [--id NAME] [--lcm URL] [--rate-hz N] [--duration S] [--wait-s S]\n"
            "                     [--rate-pct-s R] [--authority-pct A]\n"
            "                     [--axis-collective AX] [--axis-long AX] [--axis-lat AX] [--axis-pedal AX]\n"
            "                     [--take-over]\n"
            "                     [--view [pilot|deck|chase|overhead]] [--view-size WxH] [--view-image WxH]\n"
            "                     [--scenario FILE] [--view-stats FILE.csv] [--pad-mappings FILE]\n"
            "       disim station --auto TASK.ini [--id NAME] [--lcm URL] [--scenario FILE] [--duration S] [--wait-s S]\n"
            "       disim station --list\n"
            "  Sends nothing until a heli_state_t brings the controls the loop flies (--wait-s, 10,\n"
            "  then exit 1): they are the reference the controls start from.\n"
            "  --keyboard   (the default) keys in this terminal: w/s collective, arrows cyclic,\n"
            "               a/d pedal, each moving while held at --rate-pct-s %% of travel a second\n"
            "               (10); space brings cyclic and pedal back to the reference; t takes the\n"
            "               controls over; q quits\n"
            "  --device     an evdev joystick or gamepad: a spring-centred stick's deflection moves\n"
            "               its control up to +-A (--authority-pct, 50) %% about the force-trim\n"
            "               reference; BTN_TL sets the reference to the present controls, BTN_TR\n"
            "               (held) frees it and sets it where let go; BTN_START (held) takes the\n"
            "               controls over. AX is an axis name or number, ':invert' to reverse it,\n"
            "               ':lever' for a lever that stays put (picked up at the reference);\n"
            "               defaults: collective ABS_Y:invert, long ABS_RY, lat ABS_RX, pedal ABS_X\n"
            "  --script     rows time_s,collective,long,lat,pedal (percent), interpolated linearly,\n"
            "               the last row held: a stick's positions, flown as --device's are (cyclic\n"
            "               and pedals spring-centred, 50 their centre; the collective a lever picked\n"
            "               up at the flown controls), so 50 everywhere flies the controls taken\n"
            "               over; --script-absolute: the rows are the controls themselves (the loop\n"
            "               blends them in from the flown controls)\n"
            "  --auto       the automated pilot flies the task file (as disim fly --pilot auto): it\n"
            "               puts the flight at the task's start (a REPOSITION when it is elsewhere),\n"
            "               then publishes its controls once per heli_state_t received; the aircraft\n"
            "               and ship from the loop's run_info_t, or --scenario's; ends when the task\n"
            "               is done (exit 0) and says the touchdown; --wait-s (60) for the flight\n"
            "  --list       the evdev devices and their axes\n"
            "  publishes pilot_input_t on DISIM_PILOT_INPUT at --rate-hz (50); --lcm defaults to\n"
            "  LCM_DEFAULT_URL, else udpm://239.255.76.67:7667?ttl=0 (this host only); --duration ends it S seconds after its first message;\n"
            "  --take-over sets take_over in every message (this station flies, whoever was flying)\n"
            "  --view       a window with the camera's view (pilot, the default, deck, chase,\n"
            "               overhead) and the head-up strip, drawn from the states received;\n"
            "               without --keyboard, --device or --script its keys (those above; c or\n"
            "               1-4 the camera, q or Escape quits) and a game controller (SDL's mapping\n"
            "               database; --pad-mappings adds a gamecontrollerdb.txt) fly; --view-size\n"
            "               the window (1280x720), --view-image the image drawn and scaled to it\n"
            "               (the window's size; smaller draws faster); --scenario the scene before the\n"
            "               loop's run_info_t; --view-stats a CSV of every frame; the frame rate\n"
            "               and the latency (p50, p99) in the strip and on stderr at the end\n");
}

static void list_one(void *user, const sim_station_devinfo *d)
{
    (void)user;
    printf("%s  %s\n", d->path, d->error[0] ? d->error : d->name);
    if (!d->error[0] && d->naxes == 0)
        printf("    no absolute axes\n");
    for (int i = 0; i < d->naxes; i++) {
        char nb[32];
        printf("    %-13s %3d  range %d to %d  flat %d  now %d\n",
               sim_station_axis_name(d->axis[i].code, nb, sizeof nb), d->axis[i].code, d->axis[i].min,
               d->axis[i].max, d->axis[i].flat, d->axis[i].value);
    }
}

typedef struct show_ctx {
    const char *source;
    int tty;
    char buf[4096];
} show_ctx;

static void show(void *user, const sim_station_view *v)
{
    show_ctx *s = user;
    sim_station_format(v, s->source, s->tty, s->buf, sizeof s->buf);
    fputs(s->buf, stdout);
    if (!s->tty)
        fputc('\n', stdout);
    fflush(stdout);
}

/* The command line of disim station. */
typedef struct station_args {
    const char *id, *url, *device, *script_path;
    int keyboard, list, take_over, script_absolute;
    int view, view_w, view_h;   /* --view: the window, its size */
    int view_iw, view_ih;       /* the image drawn */
    render_camera_kind view_cam;
    const char *view_size, *view_image, *view_stats, *scenario, *pad_mappings;
    const char *auto_task;      /* --auto TASK.ini: the automated pilot flies */
    double rate_hz, duration_s, wait_s, rate_pct_s, authority_pct;
    sim_station_axes axes;
} station_args;

/* The view's flags checked: -1 to go on, 2 after a message. */
static int station_parse_view(station_args *o)
{
    const char *P = "disim station";
    o->view_w = 1280;
    o->view_h = 720;
    if (o->auto_task && (o->view || o->take_over || o->script_absolute)) {
        fprintf(stderr, "%s: --auto: --view, --take-over and --script-absolute do not apply\n", P);
        return 2;
    }
    if (!o->view && (o->view_size || o->view_image || o->view_stats || (o->scenario && !o->auto_task) ||
                     o->pad_mappings)) {
        fprintf(stderr, "%s: --view-size, --view-image, --view-stats, --scenario and --pad-mappings need --view "
                        "(--scenario: or --auto)\n",
                P);
        return 2;
    }
    core_err err;
    if (o->view_size && render_size_parse(o->view_size, &o->view_w, &o->view_h, &err) != 0) {
        fprintf(stderr, "%s: --view-size %s\n", P, err.msg);
        return 2;
    }
    /* the image: the window's size unless given (smaller for a busy machine:
     * docs/benchmarks.md) */
    o->view_iw = o->view_w;
    o->view_ih = o->view_h;
    if (o->view_image && render_size_parse(o->view_image, &o->view_iw, &o->view_ih, &err) != 0) {
        fprintf(stderr, "%s: --view-image %s\n", P, err.msg);
        return 2;
    }
    return -1;
}

/* The flags into o: -1 to go on, else the exit status (0 after --help,
 * 2 after a message). */
static int station_parse(int argc, char **argv, station_args *o)
{
    const char *P = "disim station";
    memset(o, 0, sizeof *o);
    o->rate_hz = 50.0;
    o->wait_s = 0.0; /* not given: 10 s, --auto 60 s */
    o->rate_pct_s = 10.0;
    o->authority_pct = SIM_STATION_AUTHORITY_PCT;
    sim_station_axes_default(&o->axes);
    static const char *axis_flag[SIM_AXES] = {"--axis-collective", "--axis-long", "--axis-lat", "--axis-pedal"};
    const struct {
        const char *flag;
        int *out;
    } sw[] = {{"--keyboard", &o->keyboard}, {"--list", &o->list}, {"--take-over", &o->take_over},
                 {"--script-absolute", &o->script_absolute}};
    const struct {
        const char *flag;
        const char **out;
    } str[] = {{"--id", &o->id},
               {"--lcm", &o->url},
               {"--device", &o->device},
               {"--script", &o->script_path},
               {"--view-size", &o->view_size},
               {"--view-image", &o->view_image},
               {"--view-stats", &o->view_stats},
               {"--scenario", &o->scenario},
               {"--auto", &o->auto_task},
               {"--pad-mappings", &o->pad_mappings}};
    const struct {
        const char *flag;
        double lo, hi, *out;
    } num[] = {{"--rate-hz", 1.0, 1000.0, &o->rate_hz},
               {"--duration", 0.001, 1e7, &o->duration_s},
               {"--wait-s", 0.1, 1e6, &o->wait_s},
               {"--rate-pct-s", 0.5, 200.0, &o->rate_pct_s},
               {"--authority-pct", 1.0, 100.0, &o->authority_pct}};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int is_switch = 0, valued = 0, bad = 0;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage_station(stdout);
            return 0;
        }
        for (size_t k = 0; k < sizeof sw / sizeof sw[0]; k++)
            if (!strcmp(a, sw[k].flag))
                *sw[k].out = is_switch = 1;
        if (is_switch)
            continue;
        if (!strcmp(a, "--view")) {
            core_err err;
            o->view = 1;
            if (v && v[0] != '-') { /* the camera, optional */
                if (render_camera_parse(v, &o->view_cam, &err) != 0) {
                    fprintf(stderr, "%s: --view: %s\n", P, err.msg);
                    return 2;
                }
                i++;
            }
            continue;
        }
        for (size_t k = 0; k < sizeof str / sizeof str[0] && v; k++)
            if (!strcmp(a, str[k].flag))
                *str[k].out = v, valued = 1;
        for (size_t k = 0; k < sizeof num / sizeof num[0] && v; k++)
            if (!strcmp(a, num[k].flag))
                bad = app_parse_double(P, a, v, num[k].lo, num[k].hi, num[k].out), valued = 1;
        for (int k = 0; k < SIM_AXES && v; k++)
            if (!strcmp(a, axis_flag[k])) {
                core_err err;
                if ((bad = sim_station_axis_parse(v, &o->axes.axis[k], &err)) != 0)
                    fprintf(stderr, "%s: %s: %s\n", P, a, err.msg);
                valued = 1;
            }
        if (bad)
            return 2;
        if (valued) {
            i++;
            continue;
        }
        int needs = 0; /* a value flag at the end */
        for (size_t k = 0; k < sizeof str / sizeof str[0]; k++)
            needs |= !strcmp(a, str[k].flag);
        for (size_t k = 0; k < sizeof num / sizeof num[0]; k++)
            needs |= !strcmp(a, num[k].flag);
        for (int k = 0; k < SIM_AXES; k++)
            needs |= !strcmp(a, axis_flag[k]);
        if (needs)
            fprintf(stderr, "%s: %s: expected a value after it\n", P, a);
        else
            fprintf(stderr, "%s: unknown argument '%s'\n", P, a);
        usage_station(stderr);
        return 2;
    }
    if (o->keyboard + (o->device != NULL) + (o->script_path != NULL) + (o->auto_task != NULL) > 1) {
        fprintf(stderr, "%s: --keyboard, --device, --script and --auto exclude each other: choose one\n", P);
        return 2;
    }
    if (o->wait_s == 0.0)
        o->wait_s = o->auto_task ? 60.0 : 10.0;
    return station_parse_view(o);
}

/* --list: the evdev devices and their axes on stdout. */
static int station_list(void)
{
    core_err err;
    int n = sim_station_evdev_list("/dev/input", list_one, NULL, &err);
    if (n < 0 && access("/dev/input", F_OK) == 0) {
        fprintf(stderr, "disim station: --list: %s\n", err.msg);
        return 1;
    }
    if (n <= 0)
        printf("no evdev input devices in /dev/input\n");
    return 0;
}

/* The signals: the stop signals end the loop, the fatal ones restore the
 * terminal first. */
static void station_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sigemptyset(&sa.sa_mask);
    sa.sa_handler = on_stop_signal; /* no SA_RESTART: the wait returns */
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGHUP, &sa, NULL);
    sigaction(SIGQUIT, &sa, NULL);
    sa.sa_handler = on_fatal_signal;
    int fatal[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT};
    for (size_t i = 0; i < sizeof fatal / sizeof fatal[0]; i++)
        sigaction(fatal[i], &sa, NULL);
}

/* --keyboard: the terminal in raw mode (restored at exit): 0, or 1 after a
 * message. */
static int station_raw_tty(void)
{
    const char *P = "disim station";
    if (tcgetattr(STDIN_FILENO, &tty_saved) != 0) {
        fprintf(stderr, "%s: --keyboard: cannot read the terminal's settings: %s\n", P, strerror(errno));
        return 1;
    }
    struct termios raw = tty_saved;
    /* no line editing, no echo; ISIG stays so that ctrl-C is SIGINT */
    raw.c_lflag &= (tcflag_t) ~(ICANON | ECHO | IEXTEN);
    raw.c_iflag &= (tcflag_t) ~(IXON | ICRNL);
    raw.c_cc[VMIN] = 1;
    raw.c_cc[VTIME] = 0;
    tty_raw = 1;
    if (tcsetattr(STDIN_FILENO, TCSAFLUSH, &raw) != 0) {
        tty_raw = 0;
        fprintf(stderr, "%s: --keyboard: cannot set the terminal to raw mode: %s\n", P, strerror(errno));
        return 1;
    }
    atexit(tty_restore);
    return 0;
}

/* ------------------------------------------------------------- the view */
#ifdef DISIM_HAVE_OTW
static void view_quit(void *user)
{
    (void)user;
    station_stop = 1; /* as a stop signal: the station's loop ends at its next wake */
}

/* --view: the view (its scene, receive thread, input pipe) and, when the
 * window is the source, its pipe as the station's device: 0, or 1 after
 * a message. */
static int station_view_open(const station_args *o, struct otw **view, sim_station_evdev **dev,
                             sim_station_controls *start)
{
    core_err err;
    otw_opts vo;
    otw_opts_default(&vo);
    vo.scenario_path = o->scenario;
    vo.lcm_url = o->url;
    vo.camera = o->view_cam;
    vo.width = o->view_w;
    vo.height = o->view_h;
    vo.image_width = o->view_iw;
    vo.image_height = o->view_ih;
    vo.inputs = !o->keyboard && !o->device && !o->script_path;
    vo.step_pct = 0.1 * o->rate_pct_s; /* a key event moves what the terminal's does: 0.1 s at the rate */
    vo.pad_mappings = o->pad_mappings;
    vo.stats_path = o->view_stats;
    vo.quit = view_quit;
    if (!(*view = otw_create(&vo, &err))) {
        fprintf(stderr, "disim station: --view: %s\n", err.msg);
        return 1;
    }
    if (vo.inputs) {
        sim_station_axes axes;
        otw_input_axes(&axes);
        int fd = dup(otw_input_fd(*view));
        if (fd < 0 || !(*dev = sim_station_evdev_wrap(fd, &axes, &err))) {
            fprintf(stderr, "disim station: --view: the window's input: %s\n", fd < 0 ? strerror(errno) : err.msg);
            otw_destroy(*view);
            *view = NULL;
            return 1;
        }
        sim_station_controls_centre(start);
    }
    return 0;
}

static void station_view_close(struct otw *view) { otw_destroy(view); }

typedef struct loop_ctx {
    sim_station *st;
    const sim_station_run_opts *ro;
    core_err err;
} loop_ctx;

static int loop_body(void *arg)
{
    loop_ctx *c = arg;
    return sim_station_run(c->st, c->ro, &c->err) != 0 ? 1 : 0;
}

/* The window on this thread, the station's loop beside it; the view's
 * figures on stderr at the end. */
static int station_loop(sim_station *st, const sim_station_run_opts *ro, struct otw *view, core_err *err)
{
    if (!view)
        return sim_station_run(st, ro, err) != 0 ? 1 : 0;
    loop_ctx c = {st, ro, {{0}, 0}};
    int body_rc = 1;
    if (otw_run(view, loop_body, &c, &body_rc, err) != 0)
        return 1;
    otw_report r;
    otw_get_report(view, &r);
    fprintf(stderr,
            "disim station: view: %ld states received, %ld frames drawn, %ld shown in %.1f s (%.1f frames/s, "
            "SDL renderer %s); latency from a state's arrival to the frame on screen p50 %.1f ms, p99 %.1f ms, "
            "max %.1f ms; drawing p50 %.1f ms, p99 %.1f ms%s%s\n",
            r.states, r.frames_drawn, r.frames_shown, r.seconds, r.fps, r.renderer, 1e3 * r.latency_p50_s,
            1e3 * r.latency_p99_s, 1e3 * r.latency_max_s, 1e3 * r.draw_p50_s, 1e3 * r.draw_p99_s,
            r.bad_rx ? "; refused: " : "", r.bad_rx ? r.bad_last : "");
    if (body_rc != 0)
        *err = c.err;
    return body_rc;
}
#else
static int station_view_open(const station_args *o, struct otw **view, sim_station_evdev **dev,
                             sim_station_controls *start)
{
    (void)o, (void)view, (void)dev, (void)start;
    fprintf(stderr, "disim station: --view: this disim was built without SDL2 (install libsdl2-dev and build again)\n");
    return 1;
}

static void station_view_close(struct otw *view) { (void)view; }

static int station_loop(sim_station *st, const sim_station_run_opts *ro, struct otw *view, core_err *err)
{
    (void)view;
    return sim_station_run(st, ro, err) != 0 ? 1 : 0;
}
#endif

/* The station's inputs (script, device or keyboard) and its LCM side,
 * the loop with the display, the last view: the exit status. */
static int station_run(const station_args *o, const char *id, const char *source)
{
    const char *P = "disim station";
    core_err err;
    sim_station_run_opts ro;
    memset(&ro, 0, sizeof ro);
    ro.rate_hz = o->rate_hz;
    ro.duration_s = o->duration_s;
    ro.wait_s = o->wait_s;
    ro.authority_pct = o->authority_pct;
    ro.key_fd = -1;
    ro.take_over = o->take_over;
    ro.stop = &station_stop;
    sim_station_controls_centre(&ro.start);
    sim_station_script *script = NULL;
    sim_station_evdev *dev = NULL;
    sim_station_keys keys;
    if (o->script_path && !(script = sim_station_script_load(o->script_path, &err))) {
        fprintf(stderr, "%s: %s\n", P, err.msg);
        return 1;
    }
    if (o->device && !(dev = sim_station_evdev_open(o->device, &o->axes, &ro.start, &err))) {
        fprintf(stderr, "%s: %s\n", P, err.msg);
        return 1;
    }
    if (o->keyboard && !isatty(STDIN_FILENO)) {
        fprintf(stderr, "%s: --keyboard: standard input is not a terminal (use --script or --device)\n", P);
        return 1;
    }
    struct otw *view = NULL;
    if (o->view && station_view_open(o, &view, &dev, &ro.start) != 0) {
        sim_station_script_destroy(script);
        sim_station_evdev_destroy(dev);
        return 1;
    }
    sim_station_opts so = {id, o->url};
    sim_station *st = sim_station_create(&so, &err);
    if (!st) {
        fprintf(stderr, "%s: %s\n", P, err.msg);
        sim_station_script_destroy(script);
        sim_station_evdev_destroy(dev);
        station_view_close(view);
        return 1;
    }
    ro.script = script;
    ro.script_absolute = o->script_absolute;
    ro.dev = dev;
    if (o->keyboard) {
        sim_station_keys_init(&keys, o->rate_pct_s, NULL, 0.0);
        ro.keys = &keys;
        ro.key_fd = STDIN_FILENO;
    }
    station_signals();
    show_ctx sc;
    sc.source = source;
    sc.tty = isatty(STDOUT_FILENO);
    ro.show = show;
    ro.user = &sc;
    ro.show_hz = sc.tty ? 10.0 : 1.0; /* a log gets one line a second */
    int rc = o->keyboard ? station_raw_tty() : 0;
    if (rc == 0) {
        if (sc.tty) {
            tty_display = 1;
            fputs("\033[2J\033[H\033[?25l", stdout); /* clear, home, cursor hidden */
            fflush(stdout);
        } else {
            fprintf(stderr, "%s: %s waits for the flown controls on %s, then publishes on %s at %g Hz (%s)\n", P, id,
                    DISIM_CH_HELI_STATE, DISIM_CH_PILOT_INPUT, o->rate_hz, source);
        }
        rc = station_loop(st, &ro, view, &err);
        sim_station_format(sim_station_get_view(st), source, sc.tty, sc.buf, sizeof sc.buf);
        if (sc.tty)
            printf("%s\n", sc.buf);
        else
            printf("end: %s\n", sc.buf);
        fflush(stdout);
        tty_restore();
        if (rc != 0)
            fprintf(stderr, "%s: %s\n", P, err.msg);
        sim_station_script_destroy(script);
        sim_station_evdev_destroy(dev);
    }
    sim_station_destroy(st);
    station_view_close(view);
    return rc;
}

/* --auto TASK.ini: the automated pilot as a station (sim_station_auto_run);
 * the touchdown said at the end. 0, or 1 after a message. */
static int station_auto(const station_args *o, const char *id)
{
    const char *P = "disim station";
    core_err err;
    sim_station_auto_opts ao;
    memset(&ao, 0, sizeof ao);
    ao.id = id;
    ao.lcm_url = o->url;
    ao.task_path = o->auto_task;
    ao.wait_s = o->wait_s;
    ao.duration_s = o->duration_s;
    ao.stop = &station_stop;
    sim_scenario *sc = NULL;
    if (o->scenario) {
        if (!(sc = calloc(1, sizeof *sc))) {
            fprintf(stderr, "%s: out of memory\n", P);
            return 1;
        }
        if (sim_scenario_load(o->scenario, sc, &err) != 0) {
            fprintf(stderr, "%s: --scenario: %s\n", P, err.msg);
            free(sc);
            return 1;
        }
        ao.aircraft_path = sc->aircraft_path;
        ao.ship_path = sc->ship_path;
    }
    station_signals();
    fprintf(stderr, "%s: %s: the automated pilot flies %s (the aircraft and ship from %s)\n", P, id, o->auto_task,
            o->scenario ? o->scenario : "the loop's run_info_t");
    sim_station_auto_stats s;
    sim_task_result r;
    int rc = sim_station_auto_run(&ao, &s, &r, &err);
    free(sc);
    printf("end: %s: %s, %ld states flown at %.0f Hz (%ld with an older ship state), %ld sent, %ld bad received; "
           "start (%.2f, %.2f, %.2f) m in S%s; SAS %s\n",
           id, s.started ? "flew" : "did not fly", s.steps, s.rate_hz, s.unpaired, s.published, s.bad_rx,
           s.start_S_m[0], s.start_S_m[1], s.start_S_m[2], s.repositioned ? " (repositioned there)" : "",
           s.sas ? "on" : "off");
    if (s.started && r.touched)
        printf("touchdown: t %.2f s, sink %.3f m/s, drift %.3f m/s, %.3f m from the spot, heading error %.2f deg, "
               "grade %d; settled %s; task grade %d; the descent from %.2f s\n",
               r.t_touchdown_s, r.sink_mps, r.drift_mps, r.dist_m, r.td_heading_err_rad * CORE_RAD_TO_DEG,
               r.touchdown_grade, r.settled ? "yes" : "no", r.grade, r.t_descent_s);
    else if (s.started)
        printf("touchdown: none by t %.2f s; task grade %d%s\n", s.t_s, r.grade, s.reset ? " (the flight was reset)" : "");
    fflush(stdout);
    if (rc != 0) {
        fprintf(stderr, "%s: %s\n", P, err.msg);
        return 1;
    }
    return 0;
}

int cmd_station(int argc, char **argv)
{
    station_args o;
    int rc = station_parse(argc, argv, &o);
    if (rc >= 0)
        return rc;
    if (o.list)
        return station_list();
    core_err err;
    if (o.id && sim_station_id_check(o.id, &err) != 0) {
        fprintf(stderr, "disim station: --id: %s\n", err.msg);
        return 2;
    }
    if (o.auto_task) {
        char abuf[80];
        if (!o.id)
            sim_station_default_id(abuf, sizeof abuf, "auto");
        return station_auto(&o, o.id ? o.id : abuf);
    }
    int keyboard = o.keyboard || (!o.device && !o.script_path && !o.view);
    int window = !keyboard && !o.device && !o.script_path; /* --view alone: the window's keys and controllers */
    o.keyboard = keyboard;
    const char *source = window ? "window" : keyboard ? "keyboard" : o.script_path ? "script" : o.device;
    const char *dev_base = o.device ? strrchr(o.device, '/') : NULL;
    char idbuf[80];
    const char *id = o.id;
    if (!id) {
        sim_station_default_id(idbuf, sizeof idbuf,
                               window     ? "window"
                               : keyboard ? "keyboard"
                               : o.script_path ? "script"
                               : dev_base      ? dev_base + 1
                                               : o.device);
        id = idbuf;
    }
    return station_run(&o, id, source);
}
