/* sim_station.h -- the pilot station, `disim station` (sim/station.c).
 * Part of sim.h (the umbrella header). */
#ifndef DISIM_SIM_STATION_H
#define DISIM_SIM_STATION_H

#include "core.h"
#include "hfm.h"
#include "sim_task.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------- the pilot station (sim/station.c) */
/* The parts of `disim station`, the reference pilot station: the sources of
 * the four controls (a scripted CSV, the keyboard's keys, an evdev joystick
 * or gamepad) and the LCM side, which publishes pilot_input_t on
 * DISIM_PILOT_INPUT at a fixed rate and receives DISIM_HELI_STATE and
 * DISIM_SIM_STATUS (each buffer checked with disim_lcm_check_raw before it
 * is decoded; a bad one is counted, never used). Controls are percent of
 * full travel (docs/conventions.md). */
#include <signal.h>
#include <stdint.h>
typedef struct sim_station_controls {
    hfm_controls ctl;
    int trim_button, trim_release; /* held (evdev buttons) */
    int take_over;                 /* this station takes the controls (sim/pilots.c) */
} sim_station_controls;
/* All four at 50 %, the buttons released. */
void sim_station_controls_centre(sim_station_controls *c);

/* A scripted pilot: a CSV of rows time_s,collective,long,lat,pedal (times
 * not decreasing from 0, percentages 0 to 100; '#' comments, blank lines
 * and one header line allowed). Between rows the controls are interpolated
 * linearly (two rows at one time make a step), before the first row they
 * are the first row's, after the last they hold the last's. NULL with err
 * naming file and line. */
typedef struct sim_station_script sim_station_script;
sim_station_script *sim_station_script_load(const char *path, core_err *err);
/* The same on a script's text in memory (len bytes; a NUL in them is
 * refused), path naming it in messages: sim_station_script_load reads the
 * file whole and parses it here. */
sim_station_script *sim_station_script_parse(const char *text, size_t len, const char *path, core_err *err);
void sim_station_script_destroy(sim_station_script *s);
void sim_station_script_at(const sim_station_script *s, double t_s, sim_station_controls *c);

/* The keyboard in a terminal (raw bytes): w / s collective up / down, the
 * arrows the cyclic (up = forward, left = left), a / d the pedals; t takes
 * the controls over (take_over in the next message); q or ctrl-C quits.
 * A terminal sends no key-up, only the bytes of a key and then its
 * autorepeat: a byte holds its control's key down for
 * SIM_STATION_KEY_HOLD_S, renewed by every repeat, and a held key moves
 * its control at rate_pct_s (percent of travel per second, clamped to
 * 0..100), so a tap moves it rate_pct_s x SIM_STATION_KEY_HOLD_S. Space
 * brings the cyclic and the pedals back to the reference (the controls
 * flown at take-over) at the same rate; the collective is a lever and
 * stays. Escape sequences (ESC [ A, ESC O A) may arrive split across
 * reads. Times are the caller's clock (s). */
#define SIM_STATION_KEY_HOLD_S 0.1 /* longer than terminals' autorepeat interval, 30-40 ms */
typedef struct sim_station_keys {
    double rate_pct_s;
    double ref_pct[4];     /* the reference space returns to */
    double until_s[4];     /* each control's key held until then */
    int sign[4];           /* its direction (+1, -1) */
    int centring;          /* space: cyclic and pedals back to the reference */
    double t_s;            /* the time moved up to (advance) */
    int esc;     /* 0, 1 after ESC, 2 after ESC [ or ESC O */
    long presses; /* keys that moved a control */
} sim_station_keys;
enum { SIM_KEY_NONE = 0, SIM_KEY_MOVED = 1, SIM_KEY_QUIT = 2 };
/* Keys at rate_pct_s, nothing held, at time t_s; the reference ref (NULL:
 * 50 % each). */
void sim_station_keys_init(sim_station_keys *k, double rate_pct_s, const hfm_controls *ref, double t_s);
/* One byte from the terminal at t_s: SIM_KEY_NONE, SIM_KEY_MOVED (a
 * control's key held, space or t) or SIM_KEY_QUIT. c is first moved up to
 * t_s as the keys held before it say; the key's own movement comes in the
 * later advances (t sets c's take_over). */
int sim_station_keys_feed(sim_station_keys *k, unsigned char byte, double t_s, sim_station_controls *c);
/* Move c's controls from the last advance (or init) to t_s as the held
 * keys and space say. */
void sim_station_keys_advance(sim_station_keys *k, double t_s, sim_station_controls *c);

/* A joystick or gamepad through evdev (/dev/input/event*). Each control
 * reads one EV_ABS axis: code (ABS_X = 0 ...), invert (1: the axis's
 * minimum is 100 %), and the range and dead band (flat, around the
 * centre) from EVIOCGABS. The default is a common gamepad in the
 * helicopter layout: left stick up/down the collective (up = more,
 * ABS_Y inverted), left stick left/right the pedals (ABS_X), right stick
 * the cyclic (ABS_RY forward = 0 %, ABS_RX); the shoulder buttons BTN_TL
 * and BTN_TR are the force-trim set and release, BTN_START (held) takes
 * the controls over. */
enum { SIM_AXIS_COLLECTIVE = 0, SIM_AXIS_LONG = 1, SIM_AXIS_LAT = 2, SIM_AXIS_PEDAL = 3, SIM_AXES = 4 };
typedef struct sim_station_axis {
    int code, invert;
    int min, max, flat;
    int lever; /* 1: a lever that stays where it is put (a throttle); 0: spring-centred */
} sim_station_axis;
typedef struct sim_station_axes {
    sim_station_axis axis[SIM_AXES];
    int trim_button_code, trim_release_code, take_over_code; /* EV_KEY codes, -1: none */
} sim_station_axes;
void sim_station_axes_default(sim_station_axes *a);
/* "ABS_RY", "ABS_RY:invert", "ABS_THROTTLE:lever", "ABS_Z:invert:lever"
 * or a number ("4", "4:invert"): 0, or -1 with err. */
int sim_station_axis_parse(const char *s, sim_station_axis *ax, core_err *err);
/* "ABS_X" ... for an axis code, "ABS_0x.." style for others (static). */
const char *sim_station_axis_name(int code, char *buf, size_t n);
/* Percent of the axis's travel for a value (dead band, clamp, invert):
 * 50 its centre. */
double sim_station_axis_pct(const sim_station_axis *ax, int value);
/* Apply one input event (type, code, value) to c, the device's positions
 * (percent of each axis's travel) and buttons: 1 if it was one of the
 * mapped axes or buttons, else 0. */
int sim_station_axes_apply(const sim_station_axes *a, int type, int code, int value, sim_station_controls *c);

/* Force trim: what a stick's position means. The controls fly about a
 * reference, the controls flown at take-over to begin with. A
 * spring-centred axis's deflection from its centre, d in -1..1, moves its
 * control to reference + authority_pct x d (clamped to 0..100): released,
 * the stick flies the reference. The trim button (trim_button) sets the
 * reference to the present controls, as the aircraft's force-trim does;
 * the trim release (trim_release) frees the stick while held, its
 * deflection flying about the old reference, and sets the reference to
 * the controls where it is let go (the aircraft's trim release: hold, fly
 * to the new attitude, let go). A stick deflected when the reference is
 * set flies the reference until it comes back within SIM_STATION_TRIM_CENTRE
 * of its centre, so that neither setting nor letting go steps a control.
 * A lever (sim_station_axis.lever) stays where it is put: its control is
 * held at the reference until the lever is brought to it (within 1 % of
 * travel, or across it), and then follows the lever. */
#define SIM_STATION_TRIM_CENTRE 0.02 /* of a half-travel: a released stick's rest, within a dead band */
#define SIM_STATION_AUTHORITY_PCT 50.0 /* a full deflection about a centred reference reaches either stop */
typedef struct sim_station_trim {
    double authority_pct;
    int lever[SIM_AXES];
    double ref_pct[SIM_AXES];
    int wait[SIM_AXES];  /* a stick: back to centre first (1); a lever: not yet brought to the reference (+-1) */
    int button, release; /* the buttons as last seen */
    long sets;           /* references set (button or release) */
} sim_station_trim;
/* The reference ref (collective, long, lat, pedal, percent), the levers
 * from axes, pos the device's positions now. */
void sim_station_trim_init(sim_station_trim *t, double authority_pct, const sim_station_axes *axes,
                           const double ref_pct[SIM_AXES], const sim_station_controls *pos);
/* The controls c (its buttons and take_over copied) for the device's
 * positions pos; a trim button pressed or a release let go sets the
 * reference. */
void sim_station_trim_apply(sim_station_trim *t, const sim_station_controls *pos, sim_station_controls *c);

typedef struct sim_station_evdev sim_station_evdev;
/* Open the device read-only, non-blocking, read each mapped axis's range
 * and position (EVIOCGABS) into the handle's axes and c. NULL with err
 * naming the path: missing, unreadable, not an evdev device, or without
 * one of the axes (the message names it and points to --list). */
sim_station_evdev *sim_station_evdev_open(const char *path, const sim_station_axes *axes,
                                          sim_station_controls *c, core_err *err);
/* A handle on an open descriptor whose axes' ranges are already in axes (a
 * pipe of struct input_event in the tests); takes the descriptor. */
sim_station_evdev *sim_station_evdev_wrap(int fd, const sim_station_axes *axes, core_err *err);
void sim_station_evdev_destroy(sim_station_evdev *d);
int sim_station_evdev_fd(const sim_station_evdev *d);
const sim_station_axes *sim_station_evdev_axes(const sim_station_evdev *d);
/* Read every pending event (read(2) of struct input_event) into c: 0 (none
 * or some), or -1 with err when the device is gone or failed. After
 * SYN_DROPPED the axes are read again with EVIOCGABS. */
int sim_station_evdev_read(sim_station_evdev *d, sim_station_controls *c, core_err *err);

/* The evdev devices in dir ("/dev/input"), event* in order of number. */
#define SIM_STATION_MAX_DEV_AXES 64
typedef struct sim_station_devinfo {
    char path[512], name[256];
    char error[256]; /* non-empty: it could not be read (what failed) */
    int naxes;
    struct {
        int code, min, max, flat, value;
    } axis[SIM_STATION_MAX_DEV_AXES];
} sim_station_devinfo;
typedef void (*sim_station_dev_fn)(void *user, const sim_station_devinfo *d);
/* Calls fn for each device: the number of devices (0: none), or -1 with
 * err when dir cannot be read. */
int sim_station_evdev_list(const char *dir, sim_station_dev_fn fn, void *user, core_err *err);

/* The station on LCM. */
typedef struct sim_station sim_station;
typedef struct sim_station_opts {
    const char *id;      /* station_id, 1 to 63 characters [A-Za-z0-9._:/@-] */
    const char *lcm_url; /* NULL: the library default */
} sim_station_opts;
/* What the station has sent and received (plain data). */
typedef struct sim_station_view {
    const char *id;
    long published, late;  /* messages sent; deadlines missed (frames skipped) */
    int64_t last_seq;      /* -1 before the first */
    double t_s;            /* station time of the last message */
    sim_station_controls sent;
    long heli_rx, status_rx, bad_rx;
    char bad_last[256]; /* why the last bad message was refused */
    int have_heli;
    int waiting;            /* nothing sent yet: waiting for the flown controls on DISIM_HELI_STATE */
    int have_ref;
    double ref_pct[4];      /* the reference the controls fly about (the take-over's, a trim's) */
    double heli_t_s, heli_pos_S_m[3], heli_vel_S_mps[3], roll_rad, pitch_rad, yaw_rad;
    double heli_ctl_pct[4]; /* collective, long, lat, pedal as the loop flies them */
    int on_deck;
    int have_status;
    double sim_time_s, rate_hz, real_time_factor;
    int64_t overruns;
    int state; /* DISIM_SIM_STATUS_T_RUNNING ... */
    char scenario[128];
    int n_stations, listed; /* listed: this station's id is among them */
    char stations[512];     /* the ids, comma-separated */
    char active[64];        /* the station flying ("" none) */
    int32_t flags;          /* DISIM_SIM_STATUS_T_FLAG_* */
    int64_t my_received, my_refused, my_gaps; /* the loop's counts for this station (listed) */
    char message[256];      /* why the loop refused the last sim_control_t, or what ended the flight */
    /* the instructor's last command as the loop answered it (sim_status_t
     * control_*): control_result DISIM_SIM_STATUS_T_CONTROL_NONE until one */
    int64_t control_seq;
    int control_command, control_result;
    char control_message[256]; /* what was done, or why not */
    double control_t_s;        /* station time the answer first arrived */
} sim_station_view;
/* 0 for an id the station may have, else -1 with err. */
int sim_station_id_check(const char *id, core_err *err);
/* A default id: the host's name (characters an id may hold, '-' for the
 * others, at most 40) and source (at most 20), joined by '-'. */
void sim_station_default_id(char *id, size_t n, const char *source);
/* NULL with err for a bad id or an LCM URL it cannot open. */
sim_station *sim_station_create(const sim_station_opts *o, core_err *err);
void sim_station_destroy(sim_station *st);
/* The LCM descriptor to poll for received messages. */
int sim_station_fd(const sim_station *st);
/* Publish c as the next pilot_input_t (seq + 1) stamped utime: 0, or -1. */
int sim_station_publish(sim_station *st, int64_t utime, const sim_station_controls *c, core_err *err);
/* Handle every message already received (does not wait). */
void sim_station_handle(sim_station *st);
/* One received buffer of channel (DISIM_HELI_STATE or DISIM_SIM_STATUS,
 * as lcm_recv_buf_t holds it), what the LCM handlers call: checked with
 * disim_lcm_check_raw, decoded, its shown values checked finite, then
 * taken into the view (its text escaped: core_escape); otherwise counted
 * as bad with the reason. */
void sim_station_receive(sim_station *st, const char *channel, const void *buf, int size);
const sim_station_view *sim_station_get_view(const sim_station *st);
/* The view as text: tty 1, a block of lines that redraws in place (ANSI:
 * cursor home, each line cleared); tty 0, one line without escapes. */
void sim_station_format(const sim_station_view *v, const char *source, int tty, char *buf, size_t n);

/* The station's loop. It sends nothing until it has received a
 * heli_state_t, the controls the loop flies (waiting wait_s at most, then
 * an error); those are the reference: the keys start at them, a device's
 * sticks fly about them (sim_station_trim); a script's rows are its own
 * and the loop blends them in (sim/pilots.c). Then it publishes every
 * 1 / rate_hz on absolute deadlines from the first message (a deadline
 * already missed is skipped and counted as late, never published in a
 * burst), the controls from exactly one source, received messages handled
 * between deadlines, show called show_hz times a second (waiting too).
 * take_over 1: every message carries take_over (a keyboard's t, a
 * device's button: the next message, or while held). Ends at duration_s
 * (> 0) after the first message, when *stop is set, on a quit key or the
 * end of the key input: 0; < 0 with err (no state within wait_s, a device
 * gone, a failed publish). */
typedef struct sim_station_run_opts {
    double rate_hz, duration_s; /* duration_s <= 0: until stopped */
    double wait_s;              /* for the first heli_state_t (> 0) */
    const sim_station_script *script;
    /* 0 (the default): the script's rows are a stick's positions, flown
     * through the force trim as a device's are (cyclic and pedals
     * spring-centred, 50 % their centre; the collective a lever picked up
     * at the reference), so a script holding 50 % flies the controls taken
     * over; 1: its rows are the controls themselves. */
    int script_absolute;
    sim_station_evdev *dev;
    int key_fd; /* >= 0: read keys from it, with keys */
    sim_station_keys *keys;     /* rate_pct_s set; started at the reference */
    sim_station_controls start; /* the device's positions (from its open) */
    double authority_pct;       /* a device's sticks (sim_station_trim) */
    int take_over;
    const volatile sig_atomic_t *stop; /* set (by a signal handler): stop */
    void (*show)(void *user, const sim_station_view *v);
    void *user;
    double show_hz;
} sim_station_run_opts;
int sim_station_run(sim_station *st, const sim_station_run_opts *o, core_err *err);

/* ------------------------ the automated station (sim/station_auto.c) */
/* The automated pilot (sim_pilot_auto) as a station of its own, `disim
 * station --auto TASK.ini`: it receives heli_state_t, ship_state_t,
 * run_info_t and sim_status_t, starts the flight at the task's first point
 * (one sim_control_t REPOSITION when it is not there), flies one pilot
 * step per state received and publishes the pilot's controls as
 * pilot_input_t (absolute; take_over in the first). sim/station_auto.c has
 * the details. */
typedef struct sim_station_auto_opts {
    const char *id;            /* station_id (sim_station_id_check) */
    const char *lcm_url;       /* NULL: the library default */
    const char *task_path;     /* the task file, resolved against the ship */
    const char *aircraft_path; /* NULL: the aircraft and ship of run_info_t */
    const char *ship_path;
    double wait_s;             /* for the flight's messages, and between two states (> 0) */
    double duration_s;         /* > 0: end this long after the pilot's start */
    const volatile sig_atomic_t *stop; /* set (by a signal handler): stop */
    const core_log *log;
} sim_station_auto_opts;
typedef struct sim_station_auto_stats {
    int started;               /* the pilot flew */
    int repositioned;          /* a REPOSITION to the task's start was sent */
    int reset;                 /* the flight started again under the pilot (the run ended) */
    int sas, gear;             /* the pilot's options as found */
    double rate_hz;            /* the pilot's: the state rate */
    double start_S_m[3];       /* the task's start */
    long heli_rx, bad_rx, steps, unpaired, published; /* unpaired: flown with an older ship state */
    double t_s;                /* the pilot's time of the last state flown */
} sim_station_auto_stats;
/* Fly until the task is done, duration_s, *stop, or a reset: 0 (r the
 * task's result so far, s what was received and sent); < 0 with err (no
 * flight within wait_s, a file that does not load, a start that is not a
 * hover, a failed publish). */
int sim_station_auto_run(const sim_station_auto_opts *o, sim_station_auto_stats *s, sim_task_result *r,
                         core_err *err);

#ifdef __cplusplus
}
#endif

#endif
