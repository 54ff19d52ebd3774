/* station.c -- the reference pilot station's parts (`disim station`): the
 * sources of the pilot's four controls and the station's side of LCM.
 *
 * Model: a station is a sampled control input. Whatever the source, the
 * controls are held between samples and published as pilot_input_t every
 * 1 / rate_hz (50 Hz by default) on absolute deadlines of CLOCK_MONOTONIC,
 * stamped with the station's time since it started (utime, microseconds)
 * and numbered seq 0, 1, 2 ... so that the flight loop can see gaps. A
 * deadline that has already passed when the station wakes is skipped and
 * counted (late), never made up by a burst of messages: a burst would
 * arrive at the loop as one input anyway, and would look like a faster
 * station.
 *
 * Sources (controls in percent of full travel, docs/conventions.md):
 * - a script: rows time,collective,long,lat,pedal interpolated linearly in
 *   time and held after the last row (the flight-loop tests' known inputs);
 * - the keyboard: raw terminal bytes, a key held (its autorepeat) moving
 *   its control at a rate, arrows as the ANSI/VT100 cursor sequences
 *   ESC [ A..D or ESC O A..D (ECMA-48; xterm's "application cursor" mode
 *   sends the latter);
 * - evdev: the Linux input event interface (Documentation/input/input.rst
 *   and event-codes.rst of the kernel): read(2) returns whole struct
 *   input_event records; EV_ABS events carry an axis's absolute position,
 *   whose range, dead band ("flat") and current value EVIOCGABS gives;
 *   SYN_DROPPED says the kernel's buffer overflowed, the events up to the
 *   next SYN_REPORT are to be dropped and the state read again.
 *
 * Take-over: the station sends nothing until a heli_state_t has brought
 * the controls the loop flies; those are the reference the keys start at
 * and a device's sticks fly about (force trim), so that a station joining
 * a trimmed flight holds it with its hands off. Otherwise the received
 * messages (DISIM_HELI_STATE, DISIM_SIM_STATUS) are only shown.
 * Each buffer goes through disim_lcm_check_raw before lcm-gen's decoder
 * sees it (lcm 1.3.1 decodes strings without checking their NUL), and a
 * message with a non-finite value the display would show is refused too:
 * a refused message is counted and its reason kept, never shown as data.
 */
#define _GNU_SOURCE
#include "sim.h"

#include "disim_lcm.h"

/* A station script far longer than any flown (a line a step for hours). */
#define SIM_STATION_SCRIPT_MAX_BYTES (64LL * 1024 * 1024)

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <linux/input.h>
#include <lcm/lcm.h>
#include <math.h>
#include <poll.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static double clamp_pct(double v) { return v < 0.0 ? 0.0 : v > 100.0 ? 100.0 : v; }

void sim_station_controls_centre(sim_station_controls *c)
{
    memset(c, 0, sizeof *c);
    c->ctl.collective_pct = c->ctl.long_cyclic_pct = c->ctl.lat_cyclic_pct = c->ctl.pedal_pct = 50.0;
}

/* ------------------------------------------------------------- the script */
typedef struct script_row {
    double t_s, v[4];
} script_row;

struct sim_station_script {
    script_row *rows;
    int n;
};

static void script_set(sim_station_controls *c, const double v[4])
{
    c->ctl.collective_pct = v[0];
    c->ctl.long_cyclic_pct = v[1];
    c->ctl.lat_cyclic_pct = v[2];
    c->ctl.pedal_pct = v[3];
}

/* Up to 5 comma-separated numbers of a line: how many parsed, -1 when a
 * field is not a number or there are more than 5. */
static int script_fields(char *line, double out[5])
{
    int n = 0;
    char *p = line;
    for (;;) {
        char *end;
        while (*p == ' ' || *p == '\t')
            p++;
        double v = strtod(p, &end);
        if (end == p || n == 5)
            return -1;
        out[n++] = v;
        p = end;
        while (*p == ' ' || *p == '\t')
            p++;
        if (*p == '\0')
            return n;
        if (*p != ',')
            return -1;
        p++;
    }
}

sim_station_script *sim_station_script_load(const char *path, core_err *err)
{
    /* a regular file of a sane size: /dev/zero or a FIFO would never end */
    size_t len = 0;
    char *text = core_file_read(path, SIM_STATION_SCRIPT_MAX_BYTES, &len, err);
    if (!text)
        return NULL;
    sim_station_script *s = sim_station_script_parse(text, len, path, err);
    free(text);
    return s;
}

/* One row (or the header, or nothing) of a script's line p (its comment
 * and line end cut off): 0, or < 0 with err. */
static int script_row_add(sim_station_script *s, int *cap, int *header_ok, char *p, const char *path, int lineno,
                          core_err *err)
{
    static const char *col[5] = {"time", "collective", "long", "lat", "pedal"};
    while (*p == ' ' || *p == '\t')
        p++;
    if (!*p)
        return 0;
    double f[5];
    int nf = script_fields(p, f);
    if (nf < 0 && *header_ok && s->n == 0 && !strchr("+-.0123456789", *p)) {
        *header_ok = 0; /* one header line, before the first row */
        return 0;
    }
    *header_ok = 0;
    if (nf != 5)
        return core_err_set(err, -1, "%s:%d: '%s': expected 5 numbers time_s,collective,long,lat,pedal (percent)",
                            path, lineno, p);
    for (int k = 0; k < 5; k++)
        if (!isfinite(f[k]) || (k == 0 && f[k] < 0.0) || (k > 0 && (f[k] < 0.0 || f[k] > 100.0)))
            return core_err_set(err, -1, "%s:%d: %s = %g: expected %s", path, lineno, col[k], f[k],
                                k == 0 ? "a time >= 0 s" : "a percentage 0 to 100");
    if (s->n > 0 && f[0] < s->rows[s->n - 1].t_s)
        return core_err_set(err, -1,
                            "%s:%d: time %g s is before the previous row's %g s: expected times that do not decrease",
                            path, lineno, f[0], s->rows[s->n - 1].t_s);
    if (s->n == *cap) {
        int nc = *cap ? 2 * *cap : 64;
        script_row *r = realloc(s->rows, (size_t)nc * sizeof *r);
        if (!r)
            return core_err_set(err, -1, "%s: out of memory", path);
        s->rows = r;
        *cap = nc;
    }
    script_row *r = &s->rows[s->n++];
    r->t_s = f[0];
    memcpy(r->v, f + 1, sizeof r->v);
    return 0;
}

sim_station_script *sim_station_script_parse(const char *text, size_t len, const char *path, core_err *err)
{
    sim_station_script *s = calloc(1, sizeof *s);
    if (!s) {
        core_err_set(err, -1, "%s: out of memory", path);
        return NULL;
    }
    int cap = 0, lineno = 0, header_ok = 1;
    char line[1024];
    for (size_t pos = 0; pos < len;) {
        lineno++;
        const char *nl = memchr(text + pos, '\n', len - pos);
        size_t n = nl ? (size_t)(nl - (text + pos)) : len - pos;
        if (n > sizeof line - 2) {
            core_err_set(err, -1, "%s:%d: line longer than %d characters", path, lineno, (int)sizeof line - 2);
            goto fail;
        }
        if (memchr(text + pos, '\0', n)) {
            core_err_set(err, -1, "%s:%d: a NUL byte (a binary file?): expected text", path, lineno);
            goto fail;
        }
        memcpy(line, text + pos, n);
        line[n] = '\0';
        pos += n + (nl ? 1 : 0);
        line[strcspn(line, "\r#")] = '\0';
        if (script_row_add(s, &cap, &header_ok, line, path, lineno, err) != 0)
            goto fail;
    }
    if (s->n == 0) {
        core_err_set(err, -1, "%s: no rows: expected lines time_s,collective,long,lat,pedal", path);
        goto fail;
    }
    return s;
fail:
    sim_station_script_destroy(s);
    return NULL;
}

void sim_station_script_destroy(sim_station_script *s)
{
    if (!s)
        return;
    free(s->rows);
    free(s);
}

void sim_station_script_at(const sim_station_script *s, double t_s, sim_station_controls *c)
{
    const script_row *r = s->rows;
    int n = s->n;
    if (!(t_s > r[0].t_s)) { /* before the first row (or NaN): the first row */
        script_set(c, r[0].v);
        return;
    }
    /* the last row at or before t: binary search, the later of equal times */
    int lo = 0, hi = n - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (r[mid].t_s <= t_s)
            lo = mid;
        else
            hi = mid - 1;
    }
    if (lo == n - 1) {
        script_set(c, r[n - 1].v);
        return;
    }
    double w = (t_s - r[lo].t_s) / (r[lo + 1].t_s - r[lo].t_s);
    double v[4];
    for (int k = 0; k < 4; k++)
        v[k] = r[lo].v[k] + w * (r[lo + 1].v[k] - r[lo].v[k]);
    script_set(c, v);
}

/* ----------------------------------------------------------- the keyboard */
void sim_station_keys_init(sim_station_keys *k, double rate_pct_s, const hfm_controls *ref, double t_s)
{
    memset(k, 0, sizeof *k);
    k->rate_pct_s = rate_pct_s;
    k->t_s = t_s;
    k->ref_pct[0] = ref ? ref->collective_pct : 50.0;
    k->ref_pct[1] = ref ? ref->long_cyclic_pct : 50.0;
    k->ref_pct[2] = ref ? ref->lat_cyclic_pct : 50.0;
    k->ref_pct[3] = ref ? ref->pedal_pct : 50.0;
    for (int i = 0; i < 4; i++)
        k->until_s[i] = -INFINITY;
}

/* Control i's key held from t_s, in direction sign. */
static int key_hold(sim_station_keys *k, int i, int sign, double t_s)
{
    k->sign[i] = sign;
    k->until_s[i] = t_s + SIM_STATION_KEY_HOLD_S;
    if (i > 0)
        k->centring = 0; /* a cyclic or pedal key ends the return to the reference */
    k->presses++;
    return SIM_KEY_MOVED;
}

static double *ctl_of(sim_station_controls *c, int i)
{
    return i == 0 ? &c->ctl.collective_pct : i == 1 ? &c->ctl.long_cyclic_pct : i == 2 ? &c->ctl.lat_cyclic_pct
                                                                                     : &c->ctl.pedal_pct;
}

static double ctl_get(const sim_station_controls *c, int i)
{
    return i == 0 ? c->ctl.collective_pct : i == 1 ? c->ctl.long_cyclic_pct : i == 2 ? c->ctl.lat_cyclic_pct
                                                                                   : c->ctl.pedal_pct;
}

void sim_station_keys_advance(sim_station_keys *k, double t_s, sim_station_controls *c)
{
    double t0 = k->t_s;
    if (!(t_s > t0))
        return;
    k->t_s = t_s;
    for (int i = 0; i < 4; i++) {
        double *v = ctl_of(c, i);
        double held = fmin(t_s, k->until_s[i]) - t0;
        if (held > 0.0)
            *v = clamp_pct(*v + k->sign[i] * k->rate_pct_s * held);
        else if (k->centring && i > 0) {
            double step = k->rate_pct_s * (t_s - t0), e = k->ref_pct[i] - *v;
            *v = fabs(e) <= step ? k->ref_pct[i] : *v + copysign(step, e);
        }
    }
    if (k->centring && ctl_get(c, 1) == k->ref_pct[1] && ctl_get(c, 2) == k->ref_pct[2] &&
        ctl_get(c, 3) == k->ref_pct[3])
        k->centring = 0;
}

int sim_station_keys_feed(sim_station_keys *k, unsigned char b, double t_s, sim_station_controls *c)
{
    sim_station_keys_advance(k, t_s, c); /* up to the key, as held before it */
    if (k->esc == 1) {
        k->esc = (b == '[' || b == 'O') ? 2 : 0;
        if (k->esc)
            return SIM_KEY_NONE;
        /* ESC then another key: the ESC alone meant nothing; the key counts */
    } else if (k->esc == 2) {
        k->esc = 0;
        switch (b) {
        case 'A': return key_hold(k, 1, -1, t_s); /* up: stick forward */
        case 'B': return key_hold(k, 1, +1, t_s);
        case 'C': return key_hold(k, 2, +1, t_s); /* right */
        case 'D': return key_hold(k, 2, -1, t_s);
        default:
            /* another sequence (a function key: ESC [ 1 5 ~): its
             * parameter bytes 0x30-0x3F run until a final byte */
            if (b >= 0x30 && b <= 0x3f)
                k->esc = 2;
            return SIM_KEY_NONE;
        }
    }
    switch (b) {
    case 0x1b: k->esc = 1; return SIM_KEY_NONE;
    case 'w': case 'W': return key_hold(k, 0, +1, t_s);
    case 's': case 'S': return key_hold(k, 0, -1, t_s);
    case 'a': case 'A': return key_hold(k, 3, -1, t_s);
    case 'd': case 'D': return key_hold(k, 3, +1, t_s);
    case 't': case 'T':
        c->take_over = 1; /* cleared once published */
        return SIM_KEY_MOVED;
    case ' ':
        for (int i = 1; i < 4; i++)
            k->until_s[i] = -INFINITY;
        k->centring = 1;
        k->presses++;
        return SIM_KEY_MOVED;
    case 'q': case 'Q': case 0x03: return SIM_KEY_QUIT;
    default: return SIM_KEY_NONE;
    }
}

/* ------------------------------------------------------------ force trim */
void sim_station_trim_init(sim_station_trim *t, double authority_pct, const sim_station_axes *axes,
                           const double ref_pct[SIM_AXES], const sim_station_controls *pos)
{
    memset(t, 0, sizeof *t);
    t->authority_pct = authority_pct;
    for (int k = 0; k < SIM_AXES; k++) {
        t->lever[k] = axes ? axes->axis[k].lever != 0 : 0;
        t->ref_pct[k] = ref_pct[k];
    }
    t->button = pos->trim_button != 0;
    t->release = pos->trim_release != 0;
    for (int k = 0; k < SIM_AXES; k++) {
        double p = ctl_get(pos, k), e = p - ref_pct[k];
        if (t->lever[k])
            t->wait[k] = fabs(e) <= 1.0 ? 0 : e > 0.0 ? 1 : -1;
        else
            t->wait[k] = fabs(p - 50.0) / 50.0 > SIM_STATION_TRIM_CENTRE;
    }
}

void sim_station_trim_apply(sim_station_trim *t, const sim_station_controls *pos, sim_station_controls *c)
{
    for (int k = 0; k < SIM_AXES; k++) {
        double p = ctl_get(pos, k), out;
        if (t->lever[k]) {
            double e = p - t->ref_pct[k];
            if (t->wait[k] && (fabs(e) <= 1.0 || (e > 0.0 ? 1 : -1) != t->wait[k]))
                t->wait[k] = 0; /* brought to the reference */
            out = t->wait[k] ? t->ref_pct[k] : p;
        } else {
            double d = (p - 50.0) / 50.0;
            if (t->wait[k] && fabs(d) <= SIM_STATION_TRIM_CENTRE)
                t->wait[k] = 0;
            out = t->wait[k] ? t->ref_pct[k] : clamp_pct(t->ref_pct[k] + t->authority_pct * d);
        }
        *ctl_of(c, k) = out;
    }
    int button = pos->trim_button != 0, release = pos->trim_release != 0;
    if ((button && !t->button) || (!release && t->release)) {
        /* the reference where the controls are; a deflected stick back to
         * its centre before it flies again */
        for (int k = 0; k < SIM_AXES; k++) {
            t->ref_pct[k] = *ctl_of(c, k);
            if (!t->lever[k])
                t->wait[k] = fabs(ctl_get(pos, k) - 50.0) / 50.0 > SIM_STATION_TRIM_CENTRE;
        }
        t->sets++;
    }
    t->button = button;
    t->release = release;
    c->trim_button = button;
    c->trim_release = release;
    c->take_over = pos->take_over;
}

/* --------------------------------------------------------------- evdev */
static const struct {
    int code;
    const char *name;
} abs_names[] = {
    {ABS_X, "ABS_X"},           {ABS_Y, "ABS_Y"},         {ABS_Z, "ABS_Z"},         {ABS_RX, "ABS_RX"},
    {ABS_RY, "ABS_RY"},         {ABS_RZ, "ABS_RZ"},       {ABS_THROTTLE, "ABS_THROTTLE"},
    {ABS_RUDDER, "ABS_RUDDER"}, {ABS_WHEEL, "ABS_WHEEL"}, {ABS_GAS, "ABS_GAS"},     {ABS_BRAKE, "ABS_BRAKE"},
    {ABS_HAT0X, "ABS_HAT0X"},   {ABS_HAT0Y, "ABS_HAT0Y"}, {ABS_HAT1X, "ABS_HAT1X"}, {ABS_HAT1Y, "ABS_HAT1Y"},
    {ABS_HAT2X, "ABS_HAT2X"},   {ABS_HAT2Y, "ABS_HAT2Y"}, {ABS_HAT3X, "ABS_HAT3X"}, {ABS_HAT3Y, "ABS_HAT3Y"},
    {ABS_PRESSURE, "ABS_PRESSURE"}, {ABS_DISTANCE, "ABS_DISTANCE"}, {ABS_TILT_X, "ABS_TILT_X"},
    {ABS_TILT_Y, "ABS_TILT_Y"}, {ABS_MISC, "ABS_MISC"},
};

const char *sim_station_axis_name(int code, char *buf, size_t n)
{
    for (size_t i = 0; i < sizeof abs_names / sizeof abs_names[0]; i++)
        if (abs_names[i].code == code)
            return abs_names[i].name;
    snprintf(buf, n, "ABS_0x%02x", code);
    return buf;
}

void sim_station_axes_default(sim_station_axes *a)
{
    memset(a, 0, sizeof *a);
    a->axis[SIM_AXIS_COLLECTIVE] = (sim_station_axis){ABS_Y, 1, -32768, 32767, 0, 0};
    a->axis[SIM_AXIS_LONG] = (sim_station_axis){ABS_RY, 0, -32768, 32767, 0, 0};
    a->axis[SIM_AXIS_LAT] = (sim_station_axis){ABS_RX, 0, -32768, 32767, 0, 0};
    a->axis[SIM_AXIS_PEDAL] = (sim_station_axis){ABS_X, 0, -32768, 32767, 0, 0};
    a->trim_button_code = BTN_TL;
    a->trim_release_code = BTN_TR;
    a->take_over_code = BTN_START;
}

int sim_station_axis_parse(const char *s, sim_station_axis *ax, core_err *err)
{
    char name[64];
    const char *colon = strchr(s, ':');
    size_t len = colon ? (size_t)(colon - s) : strlen(s);
    int invert = 0, lever = 0, code = -1;
    for (const char *o = colon; o; o = strchr(o + 1, ':')) {
        const char *e = strchr(o + 1, ':');
        size_t ol = e ? (size_t)(e - o - 1) : strlen(o + 1);
        if (ol == 6 && !strncmp(o + 1, "invert", 6))
            invert = 1;
        else if (ol == 5 && !strncmp(o + 1, "lever", 5))
            lever = 1;
        else
            return core_err_set(err, -1, "axis '%s': expected NAME, then :invert or :lever, got ':%.*s'", s, (int)ol,
                                o + 1);
    }
    if (len == 0 || len >= sizeof name)
        return core_err_set(err, -1, "axis '%s': expected an axis name (ABS_X, ABS_RY ...) or number", s);
    memcpy(name, s, len);
    name[len] = '\0';
    for (size_t i = 0; i < sizeof abs_names / sizeof abs_names[0]; i++)
        if (!strcasecmp(abs_names[i].name, name))
            code = abs_names[i].code;
    if (code < 0) {
        char *end;
        long v = strtol(name, &end, 0);
        if (*end || end == name || v < 0 || v > ABS_MAX)
            return core_err_set(err, -1, "axis '%s': expected an axis name (ABS_X, ABS_RY ...) or a number 0 to %d",
                                s, ABS_MAX);
        code = (int)v;
    }
    ax->code = code;
    ax->invert = invert;
    ax->lever = lever;
    return 0;
}

double sim_station_axis_pct(const sim_station_axis *ax, int value)
{
    double lo = ax->min, hi = ax->max;
    if (!(hi > lo))
        return 50.0;
    double mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo), flat = ax->flat > 0 ? ax->flat : 0.0;
    double x = (value - mid) / half; /* -1 .. 1 */
    if (flat > 0.0 && flat < half) {
        /* the dead band around the centre reads 50 %; outside it the rest
         * of the travel is stretched to the stops (no step at its edge) */
        double f = flat / half, ax_ = fabs(x);
        x = ax_ <= f ? 0.0 : copysign((ax_ - f) / (1.0 - f), x);
    }
    double pct = clamp_pct(50.0 + 50.0 * x);
    return ax->invert ? 100.0 - pct : pct;
}

int sim_station_axes_apply(const sim_station_axes *a, int type, int code, int value, sim_station_controls *c)
{
    if (type == EV_ABS) {
        double *dst[SIM_AXES] = {&c->ctl.collective_pct, &c->ctl.long_cyclic_pct, &c->ctl.lat_cyclic_pct,
                                 &c->ctl.pedal_pct};
        int hit = 0;
        for (int k = 0; k < SIM_AXES; k++)
            if (a->axis[k].code == code) {
                *dst[k] = sim_station_axis_pct(&a->axis[k], value);
                hit = 1;
            }
        return hit;
    }
    if (type == EV_KEY && code >= 0 && code == a->trim_button_code) {
        c->trim_button = value != 0;
        return 1;
    }
    if (type == EV_KEY && code >= 0 && code == a->trim_release_code) {
        c->trim_release = value != 0;
        return 1;
    }
    if (type == EV_KEY && code >= 0 && code == a->take_over_code) {
        c->take_over = value != 0;
        return 1;
    }
    return 0;
}

struct sim_station_evdev {
    int fd;
    char path[512];
    sim_station_axes axes;
    int dropping; /* after SYN_DROPPED, until the next SYN_REPORT */
    size_t carry; /* bytes of a partial event (a pipe) */
    unsigned char buf[64 * sizeof(struct input_event)];
};

static int test_bit(const unsigned long *bits, int n)
{
    const int w = (int)(8 * sizeof(unsigned long));
    return (int)((bits[n / w] >> (n % w)) & 1UL);
}

/* Each mapped axis's range and position from the device; c (if not NULL)
 * set to the positions. */
static int evdev_absinfo(sim_station_evdev *d, sim_station_controls *c, core_err *err)
{
    static const char *what[SIM_AXES] = {"collective", "long cyclic", "lat cyclic", "pedal"};
    static const char *flag[SIM_AXES] = {"--axis-collective", "--axis-long", "--axis-lat", "--axis-pedal"};
    unsigned long bits[ABS_CNT / (8 * sizeof(unsigned long)) + 1];
    memset(bits, 0, sizeof bits);
    if (ioctl(d->fd, EVIOCGBIT(EV_ABS, sizeof bits), bits) < 0)
        return core_err_set(err, -1, "%s: cannot read its axes (EVIOCGBIT): %s", d->path, strerror(errno));
    for (int k = 0; k < SIM_AXES; k++) {
        sim_station_axis *ax = &d->axes.axis[k];
        struct input_absinfo ai;
        char nb[32];
        if (!test_bit(bits, ax->code) || ioctl(d->fd, EVIOCGABS(ax->code), &ai) < 0)
            return core_err_set(err, -1, "%s: has no axis %s (for the %s): 'disim station --list' names its axes; choose one with %s",
                                d->path, sim_station_axis_name(ax->code, nb, sizeof nb), what[k], flag[k]);
        ax->min = ai.minimum;
        ax->max = ai.maximum;
        ax->flat = ai.flat;
        if (c)
            sim_station_axes_apply(&d->axes, EV_ABS, ax->code, ai.value, c);
    }
    return 0;
}

sim_station_evdev *sim_station_evdev_open(const char *path, const sim_station_axes *axes,
                                          sim_station_controls *c, core_err *err)
{
    sim_station_evdev *d = calloc(1, sizeof *d);
    if (!d) {
        core_err_set(err, -1, "%s: out of memory", path);
        return NULL;
    }
    snprintf(d->path, sizeof d->path, "%s", path);
    d->axes = *axes;
    d->fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    int version = 0;
    if (d->fd < 0) {
        core_err_set(err, -1, "%s: %s%s", path, strerror(errno),
                     errno == EACCES ? " (the 'input' group can read evdev devices)" : "");
    } else if (ioctl(d->fd, EVIOCGVERSION, &version) < 0) {
        core_err_set(err, -1, "%s: not an evdev input device (%s)", path, strerror(errno));
    } else if (evdev_absinfo(d, c, err) == 0) {
        return d;
    }
    sim_station_evdev_destroy(d);
    return NULL;
}

sim_station_evdev *sim_station_evdev_wrap(int fd, const sim_station_axes *axes, core_err *err)
{
    sim_station_evdev *d = calloc(1, sizeof *d);
    if (!d) {
        core_err_set(err, -1, "evdev: out of memory");
        close(fd);
        return NULL;
    }
    snprintf(d->path, sizeof d->path, "fd %d", fd);
    d->fd = fd;
    d->axes = *axes;
    int fl = fcntl(fd, F_GETFL);
    if (fl >= 0)
        fcntl(fd, F_SETFL, fl | O_NONBLOCK);
    return d;
}

void sim_station_evdev_destroy(sim_station_evdev *d)
{
    if (!d)
        return;
    if (d->fd >= 0)
        close(d->fd);
    free(d);
}

const sim_station_axes *sim_station_evdev_axes(const sim_station_evdev *d) { return &d->axes; }

int sim_station_evdev_fd(const sim_station_evdev *d) { return d->fd; }

int sim_station_evdev_read(sim_station_evdev *d, sim_station_controls *c, core_err *err)
{
    const size_t ev = sizeof(struct input_event);
    for (;;) {
        ssize_t n = read(d->fd, d->buf + d->carry, sizeof d->buf - d->carry);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
            return 0;
        if (n < 0)
            return core_err_set(err, -1, "%s: %s", d->path,
                                errno == ENODEV ? "the device is gone (unplugged?)" : strerror(errno));
        if (n == 0)
            return core_err_set(err, -1, "%s: end of input", d->path);
        size_t have = d->carry + (size_t)n, i = 0;
        for (; i + ev <= have; i += ev) {
            struct input_event e;
            memcpy(&e, d->buf + i, ev);
            if (e.type == EV_SYN && e.code == SYN_DROPPED) {
                d->dropping = 1;
                continue;
            }
            if (d->dropping) {
                if (e.type == EV_SYN && e.code == SYN_REPORT) {
                    d->dropping = 0;
                    /* the state now, from the device (a pipe has none:
                     * its events carry on from here) */
                    core_err ignore;
                    evdev_absinfo(d, c, &ignore);
                }
                continue;
            }
            sim_station_axes_apply(&d->axes, e.type, e.code, e.value, c);
        }
        d->carry = have - i;
        memmove(d->buf, d->buf + i, d->carry);
    }
}

static int event_number(const char *name) { return atoi(name + 5); }

static int event_filter(const struct dirent *e) { return !strncmp(e->d_name, "event", 5); }

static int event_cmp(const struct dirent **a, const struct dirent **b)
{
    return event_number((*a)->d_name) - event_number((*b)->d_name);
}

int sim_station_evdev_list(const char *dir, sim_station_dev_fn fn, void *user, core_err *err)
{
    struct dirent **names = NULL;
    int n = scandir(dir, &names, event_filter, event_cmp);
    if (n < 0)
        return core_err_set(err, -1, "%s: %s", dir, strerror(errno));
    for (int i = 0; i < n; i++) {
        sim_station_devinfo *info = calloc(1, sizeof *info);
        if (info) {
            snprintf(info->path, sizeof info->path, "%s/%s", dir, names[i]->d_name);
            int fd = open(info->path, O_RDONLY | O_NONBLOCK | O_CLOEXEC), version = 0;
            unsigned long bits[ABS_CNT / (8 * sizeof(unsigned long)) + 1];
            memset(bits, 0, sizeof bits);
            if (fd < 0)
                snprintf(info->error, sizeof info->error, "cannot open: %s%s", strerror(errno),
                         errno == EACCES ? " (the 'input' group can read evdev devices)" : "");
            else if (ioctl(fd, EVIOCGVERSION, &version) < 0)
                snprintf(info->error, sizeof info->error, "not an evdev device: %s", strerror(errno));
            else {
                if (ioctl(fd, EVIOCGNAME(sizeof info->name - 1), info->name) < 0)
                    snprintf(info->name, sizeof info->name, "?");
                if (ioctl(fd, EVIOCGBIT(EV_ABS, sizeof bits), bits) >= 0)
                    for (int code = 0; code < ABS_CNT && info->naxes < SIM_STATION_MAX_DEV_AXES; code++) {
                        struct input_absinfo ai;
                        if (test_bit(bits, code) && ioctl(fd, EVIOCGABS(code), &ai) >= 0) {
                            info->axis[info->naxes].code = code;
                            info->axis[info->naxes].min = ai.minimum;
                            info->axis[info->naxes].max = ai.maximum;
                            info->axis[info->naxes].flat = ai.flat;
                            info->axis[info->naxes].value = ai.value;
                            info->naxes++;
                        }
                    }
            }
            if (fd >= 0)
                close(fd);
            fn(user, info);
            free(info);
        }
        free(names[i]);
    }
    free(names);
    return n;
}

/* ---------------------------------------------------------- LCM station */
struct sim_station {
    lcm_t *lc;
    char id[64];
    int64_t seq;
    lcm_subscription_t *sub_heli, *sub_status;
    sim_station_view v;
};

static void refuse(sim_station *st, const char *ch, const char *why)
{
    st->v.bad_rx++;
    snprintf(st->v.bad_last, sizeof st->v.bad_last, "%s: %s", ch, why);
}

static int all_finite(const double *x, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(x[i]))
            return 0;
    return 1;
}

static void rx_heli(sim_station *st, const char *ch, const void *buf, int size)
{
    char err[200];
    if (disim_lcm_check_raw("heli_state_t", buf, size, err, sizeof err) != 0) {
        refuse(st, ch, err);
        return;
    }
    disim_heli_state_t m;
    memset(&m, 0, sizeof m);
    if (disim_heli_state_t_decode(buf, 0, size, &m) < 0) {
        refuse(st, ch, "heli_state_t: cannot decode");
        return;
    }
    double ctl[4] = {m.collective_pct, m.long_cyclic_pct, m.lat_cyclic_pct, m.pedal_pct};
    if (disim_lcm_check_heli_state(&m, err, sizeof err) != 0) {
        refuse(st, ch, err);
    } else {
        sim_station_view *v = &st->v;
        v->heli_rx++;
        v->have_heli = 1;
        v->heli_t_s = 1e-6 * (double)m.utime;
        memcpy(v->heli_pos_S_m, m.pos_S_m, sizeof v->heli_pos_S_m);
        memcpy(v->heli_vel_S_mps, m.vel_S_mps, sizeof v->heli_vel_S_mps);
        v->roll_rad = m.roll_rad;
        v->pitch_rad = m.pitch_rad;
        v->yaw_rad = m.yaw_rad;
        memcpy(v->heli_ctl_pct, ctl, sizeof ctl);
        v->on_deck = m.on_deck != 0;
    }
    disim_heli_state_t_decode_cleanup(&m);
}

static void rx_status(sim_station *st, const char *ch, const void *buf, int size)
{
    char err[200];
    if (disim_lcm_check_raw("sim_status_t", buf, size, err, sizeof err) != 0) {
        refuse(st, ch, err);
        return;
    }
    disim_sim_status_t m;
    memset(&m, 0, sizeof m);
    if (disim_sim_status_t_decode(buf, 0, size, &m) < 0) {
        refuse(st, ch, "sim_status_t: cannot decode");
        return;
    }
    double x[3] = {m.sim_time_s, m.rate_hz, m.real_time_factor};
    if (!all_finite(x, 3)) {
        refuse(st, ch, "sim_status_t: sim_time_s, rate_hz or real_time_factor is not finite");
    } else {
        sim_station_view *v = &st->v;
        v->status_rx++;
        v->have_status = 1;
        v->sim_time_s = m.sim_time_s;
        v->rate_hz = m.rate_hz;
        v->real_time_factor = m.real_time_factor;
        v->overruns = m.overruns;
        v->state = m.state;
        /* every string shown is the network's: escaped (core_escape) */
        core_escape(m.scenario, v->scenario, sizeof v->scenario);
        v->n_stations = m.n_stations;
        v->listed = 0;
        v->stations[0] = '\0';
        v->flags = m.flags;
        v->my_received = v->my_refused = v->my_gaps = 0;
        core_escape(m.active_station >= 0 && m.active_station < m.n_stations ? m.station_ids[m.active_station] : "",
                    v->active, sizeof v->active);
        core_escape(m.message, v->message, sizeof v->message);
        if (m.control_result != DISIM_SIM_STATUS_T_CONTROL_NONE &&
            (m.control_seq != v->control_seq || v->control_result == DISIM_SIM_STATUS_T_CONTROL_NONE))
            v->control_t_s = v->t_s;
        v->control_seq = m.control_seq;
        v->control_command = m.control_command;
        v->control_result = m.control_result;
        core_escape(m.control_message, v->control_message, sizeof v->control_message);
        size_t used = 0;
        for (int i = 0; i < m.n_stations; i++) {
            if (!strcmp(m.station_ids[i], st->id)) {
                v->listed = 1;
                v->my_received = m.station_received[i];
                v->my_refused = m.station_refused[i];
                v->my_gaps = m.station_gaps[i];
            }
            char idv[256];
            core_escape(m.station_ids[i], idv, sizeof idv);
            int w = snprintf(v->stations + used, sizeof v->stations - used, "%s%s", i ? ", " : "", idv);
            if (w < 0 || (size_t)w >= sizeof v->stations - used) {
                used = sizeof v->stations - 1;
                snprintf(v->stations + sizeof v->stations - 4, 4, "...");
            } else {
                used += (size_t)w;
            }
        }
    }
    disim_sim_status_t_decode_cleanup(&m);
}

void sim_station_receive(sim_station *st, const char *channel, const void *buf, int size)
{
    if (!strcmp(channel, DISIM_CH_HELI_STATE))
        rx_heli(st, channel, buf, size);
    else if (!strcmp(channel, DISIM_CH_SIM_STATUS))
        rx_status(st, channel, buf, size);
    else
        refuse(st, channel, "not a channel the station reads");
}

static void on_raw(const lcm_recv_buf_t *rb, const char *ch, void *user)
{
    sim_station_receive(user, ch, rb->data, (int)rb->data_size);
}

static int id_ok(const char *id)
{
    size_t n = id ? strlen(id) : 0;
    if (n < 1 || n > 63)
        return 0;
    for (size_t i = 0; i < n; i++)
        if (!((id[i] >= 'a' && id[i] <= 'z') || (id[i] >= 'A' && id[i] <= 'Z') || (id[i] >= '0' && id[i] <= '9') ||
              strchr("._:/@-", id[i])))
            return 0;
    return 1;
}

int sim_station_id_check(const char *id, core_err *err)
{
    if (id_ok(id))
        return 0;
    return core_err_set(err, -1, "station id '%s': expected 1 to 63 characters of A-Z a-z 0-9 . _ : / @ -",
                        id ? id : "");
}

void sim_station_default_id(char *id, size_t n, const char *source)
{
    char host[64] = "station";
    if (gethostname(host, sizeof host) != 0)
        snprintf(host, sizeof host, "station");
    host[sizeof host - 1] = '\0';
    for (char *p = host; *p; p++)
        if (!((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') || *p == '-'))
            *p = '-';
    snprintf(id, n, "%.40s-%.20s", host, source);
}

sim_station *sim_station_create(const sim_station_opts *o, core_err *err)
{
    if (sim_station_id_check(o->id, err) != 0)
        return NULL;
    sim_station *st = calloc(1, sizeof *st);
    if (!st) {
        core_err_set(err, -1, "station: out of memory");
        return NULL;
    }
    snprintf(st->id, sizeof st->id, "%s", o->id);
    st->v.id = st->id;
    st->v.last_seq = -1;
    st->v.control_seq = -1;
    sim_station_controls_centre(&st->v.sent);
    st->lc = lcm_create(disim_lcm_url(o->lcm_url));
    if (!st->lc) {
        core_err_set(err, -1, "LCM '%s': cannot create (a bad URL, or no multicast route: see docs/conventions.md, LCM)",
                     o->lcm_url ? o->lcm_url : "(default)");
        free(st);
        return NULL;
    }
    st->sub_heli = lcm_subscribe(st->lc, DISIM_CH_HELI_STATE, on_raw, st);
    st->sub_status = lcm_subscribe(st->lc, DISIM_CH_SIM_STATUS, on_raw, st);
    if (!st->sub_heli || !st->sub_status) {
        core_err_set(err, -1, "LCM: cannot subscribe to %s and %s", DISIM_CH_HELI_STATE, DISIM_CH_SIM_STATUS);
        sim_station_destroy(st);
        return NULL;
    }
    return st;
}

void sim_station_destroy(sim_station *st)
{
    if (!st)
        return;
    if (st->sub_heli)
        lcm_unsubscribe(st->lc, st->sub_heli);
    if (st->sub_status)
        lcm_unsubscribe(st->lc, st->sub_status);
    lcm_destroy(st->lc);
    free(st);
}

int sim_station_fd(const sim_station *st) { return lcm_get_fileno(st->lc); }

int sim_station_publish(sim_station *st, int64_t utime, const sim_station_controls *c, core_err *err)
{
    disim_pilot_input_t m;
    memset(&m, 0, sizeof m);
    m.utime = utime;
    m.station_id = st->id;
    m.seq = st->seq;
    m.collective_pct = clamp_pct(c->ctl.collective_pct);
    m.long_cyclic_pct = clamp_pct(c->ctl.long_cyclic_pct);
    m.lat_cyclic_pct = clamp_pct(c->ctl.lat_cyclic_pct);
    m.pedal_pct = clamp_pct(c->ctl.pedal_pct);
    m.trim_button = c->trim_button != 0;
    m.trim_release = c->trim_release != 0;
    m.take_over = c->take_over != 0;
    if (disim_pilot_input_t_publish(st->lc, DISIM_CH_PILOT_INPUT, &m) != 0)
        return core_err_set(err, -1, "LCM: publishing on %s failed", DISIM_CH_PILOT_INPUT);
    st->v.last_seq = st->seq++;
    st->v.published++;
    st->v.t_s = 1e-6 * (double)utime;
    st->v.sent = *c;
    return 0;
}

void sim_station_handle(sim_station *st)
{
    while (lcm_handle_timeout(st->lc, 0) > 0)
        ;
}

const sim_station_view *sim_station_get_view(const sim_station *st) { return &st->v; }

/* ------------------------------------------------------------ the display */
typedef struct outbuf {
    char *p;
    size_t n, used;
} outbuf;

__attribute__((format(printf, 2, 3))) static void out(outbuf *o, const char *fmt, ...)
{
    if (o->used + 1 >= o->n)
        return;
    va_list ap;
    va_start(ap, fmt);
    int w = vsnprintf(o->p + o->used, o->n - o->used, fmt, ap);
    va_end(ap);
    if (w > 0)
        o->used = o->used + (size_t)w < o->n ? o->used + (size_t)w : o->n - 1;
}

static const char *state_name(int s)
{
    return s == DISIM_SIM_STATUS_T_RUNNING ? "RUNNING"
           : s == DISIM_SIM_STATUS_T_PAUSED ? "PAUSED"
           : s == DISIM_SIM_STATUS_T_STOPPED ? "STOPPED"
                                             : "state ?";
}

/* The loop's flags in words ("" none): the gear's reports first. */
static void flag_words(int32_t f, char *b, size_t n)
{
    snprintf(b, n, "%s%s%s%s%s%s%s%s%s%s%s", f & DISIM_SIM_STATUS_T_FLAG_CRASH ? " CRASH" : "",
             f & DISIM_SIM_STATUS_T_FLAG_TIP_OVER ? " TIP-OVER" : "", f & DISIM_SIM_STATUS_T_FLAG_SLIDE ? " SLIDE" : "",
             f & DISIM_SIM_STATUS_T_FLAG_INPUT_HELD ? " INPUT-HELD" : "",
             f & DISIM_SIM_STATUS_T_FLAG_CONTROLS_BLENDING ? " CONTROLS-BLENDING" : "",
             f & DISIM_SIM_STATUS_T_FLAG_FREE_STREAM ? " FREE-STREAM" : "",
             f & DISIM_SIM_STATUS_T_FLAG_FIELD_BLENDING ? " FIELD-BLENDING" : "",
             f & DISIM_SIM_STATUS_T_FLAG_PAUSED ? " PAUSED" : "", f & DISIM_SIM_STATUS_T_FLAG_REPLAY ? " REPLAY" : "",
             f & DISIM_SIM_STATUS_T_FLAG_ROTOR_INTERACTION ? " ROTOR-INTERACTION" : "",
             f & DISIM_SIM_STATUS_T_FLAG_SAS_OFF ? " SAS-OFF" : "");
}

/* The instructor's last command as answered ("" none yet): the loop's
 * words (they name the command), REFUSED before a refusal's. */
static void ios_words(const sim_station_view *v, char *b, size_t n)
{
    if (n)
        b[0] = '\0';
    int ok = v->control_result == DISIM_SIM_STATUS_T_CONTROL_ACCEPTED;
    if (!ok && v->control_result != DISIM_SIM_STATUS_T_CONTROL_REFUSED)
        return;
    if (v->control_message[0])
        snprintf(b, n, "%s%s", ok ? "" : "REFUSED: ", v->control_message);
    else
        snprintf(b, n, "%s %s", sim_ios_command_name(v->control_command), ok ? "done" : "REFUSED");
}

/* The loop's message unless it is the refusal the instructor's line shows. */
static const char *loop_message(const sim_station_view *v)
{
    return v->control_result == DISIM_SIM_STATUS_T_CONTROL_REFUSED && !strcmp(v->message, v->control_message)
               ? ""
               : v->message;
}

void sim_station_format(const sim_station_view *v, const char *source, int tty, char *buf, size_t n)
{
    char flags[128];
    flag_words(v->flags, flags, sizeof flags);
    outbuf o = {buf, n, 0};
    if (n)
        buf[0] = '\0';
    const double R = CORE_RAD_TO_DEG;
    const sim_station_controls *c = &v->sent;
    if (!tty) {
        out(&o, "t %.1f s sent %ld seq %lld late %ld", v->t_s, v->published, (long long)v->last_seq, v->late);
        if (v->waiting)
            out(&o, " | waiting for the flown controls on %s", DISIM_CH_HELI_STATE);
        else
            out(&o, " | ctl %.1f %.1f %.1f %.1f", c->ctl.collective_pct, c->ctl.long_cyclic_pct,
                c->ctl.lat_cyclic_pct, c->ctl.pedal_pct);
        if (v->have_ref)
            out(&o, " ref %.1f %.1f %.1f %.1f", v->ref_pct[0], v->ref_pct[1], v->ref_pct[2], v->ref_pct[3]);
        if (v->have_heli)
            out(&o, " | heli h %.2f m x %.2f y %.2f roll %.1f pitch %.1f yaw %.1f deg", -v->heli_pos_S_m[2],
                v->heli_pos_S_m[0], v->heli_pos_S_m[1], v->roll_rad * R, v->pitch_rad * R, v->yaw_rad * R);
        else
            out(&o, " | heli none");
        if (v->have_status)
            out(&o, " | sim t %.2f s %s %.1f Hz rtf %.2f overruns %lld stations %d%s active %s%s", v->sim_time_s,
                state_name(v->state), v->rate_hz, v->real_time_factor, (long long)v->overruns, v->n_stations,
                v->listed ? " (listed)" : "", v->active[0] ? v->active : "none", flags);
        else
            out(&o, " | sim none");
        char ios[320];
        ios_words(v, ios, sizeof ios);
        if (ios[0])
            out(&o, " | instructor %s", ios);
        out(&o, " | rx heli %ld status %ld bad %ld", v->heli_rx, v->status_rx, v->bad_rx);
        if (v->bad_rx)
            out(&o, " (%s)", v->bad_last);
        return;
    }
    /* cursor home; every line cleared to its end; the rest cleared below */
    const char *E = "\033[K\n";
    out(&o, "\033[H\033[1mdisim station %s\033[0m (%s)   t %.1f s   sent %ld (seq %lld)   late %ld%s", v->id,
        source, v->t_s, v->published, (long long)v->last_seq, v->late, E);
    if (v->waiting)
        out(&o, "  \033[1mwaiting for the flown controls on %s: nothing sent until they arrive\033[0m%s",
            DISIM_CH_HELI_STATE, E);
    else
        out(&o, "  sending     collective %5.1f %%   long cyclic %5.1f %%   lat cyclic %5.1f %%   pedal %5.1f %%%s%s",
            c->ctl.collective_pct, c->ctl.long_cyclic_pct, c->ctl.lat_cyclic_pct, c->ctl.pedal_pct,
            c->trim_button ? "   TRIM" : c->trim_release ? "   TRIM RELEASE" : c->take_over ? "   TAKE OVER" : "", E);
    if (v->have_ref)
        out(&o, "  reference   collective %5.1f %%   long cyclic %5.1f %%   lat cyclic %5.1f %%   pedal %5.1f %%%s",
            v->ref_pct[0], v->ref_pct[1], v->ref_pct[2], v->ref_pct[3], E);
    if (v->have_heli) {
        out(&o, "  helicopter  height over deck %6.2f m   from the spot x %+7.2f m (fwd)  y %+7.2f m (stbd)%s%s",
            -v->heli_pos_S_m[2], v->heli_pos_S_m[0], v->heli_pos_S_m[1], v->on_deck ? "   ON DECK" : "", E);
        out(&o, "              roll %+6.1f deg   pitch %+6.1f deg   yaw %6.1f deg   t %.2f s%s", v->roll_rad * R,
            v->pitch_rad * R, v->yaw_rad * R, v->heli_t_s, E);
        out(&o, "              flown: collective %5.1f %%   long %5.1f %%   lat %5.1f %%   pedal %5.1f %%%s",
            v->heli_ctl_pct[0], v->heli_ctl_pct[1], v->heli_ctl_pct[2], v->heli_ctl_pct[3], E);
    } else {
        out(&o, "  helicopter  (nothing on %s yet)%s", DISIM_CH_HELI_STATE, E);
    }
    if (v->have_status) {
        out(&o, "  sim         t %.2f s   %s   rate %.1f Hz   real time x%.2f   overruns %lld   %s%s", v->sim_time_s,
            state_name(v->state), v->rate_hz, v->real_time_factor, (long long)v->overruns, v->scenario, E);
        out(&o, "              stations (%d): %s   flying: %s%s%s", v->n_stations, v->n_stations ? v->stations : "none",
            v->active[0] ? v->active : "none", !strcmp(v->active, v->id) ? " (this one)" : "", E);
        if (v->listed)
            out(&o, "              this station: taken %lld   refused %lld   missing %lld%s", (long long)v->my_received,
                (long long)v->my_refused, (long long)v->my_gaps, E);
        else
            out(&o, "              this station: not among them%s", E);
        const char *msg = loop_message(v);
        if (flags[0] || msg[0])
            out(&o, "              \033[1m%s\033[0m%s%s%s", flags + (flags[0] == ' '), msg[0] ? "   " : "", msg, E);
        char ios[320];
        ios_words(v, ios, sizeof ios);
        if (ios[0])
            out(&o, "  instructor  %s%s%s   (%.0f s ago)%s",
                v->control_result == DISIM_SIM_STATUS_T_CONTROL_REFUSED ? "\033[1m" : "", ios,
                v->control_result == DISIM_SIM_STATUS_T_CONTROL_REFUSED ? "\033[0m" : "",
                v->t_s >= v->control_t_s ? v->t_s - v->control_t_s : 0.0, E);
    } else {
        out(&o, "  sim         (nothing on %s yet)%s", DISIM_CH_SIM_STATUS, E);
    }
    out(&o, "  received    heli %ld   status %ld   bad %ld%s%s%s", v->heli_rx, v->status_rx, v->bad_rx,
        v->bad_rx ? "   last: " : "", v->bad_rx ? v->bad_last : "", E);
    if (!strcmp(source, "keyboard"))
        out(&o, "  keys        w/s collective   arrows cyclic   a/d pedal (held: they move)   space cyclic and pedal back "
                "to the reference   t take over   q quit%s", E);
    out(&o, "\033[J");
}

/* --------------------------------------------------------------- the loop */
/* Wait for the pollable descriptors until wake (monotonic s): LCM handled,
 * pf[1] (a device or the keys, fd -1: none) returned ready in *ready. */
static int station_poll(sim_station *st, int fd2, double wake, int *ready, core_err *err)
{
    struct pollfd pf[2] = {{sim_station_fd(st), POLLIN, 0}, {fd2, POLLIN, 0}};
    double dt = wake - core_monotonic_s();
    if (dt < 0.0)
        dt = 0.0;
    struct timespec ts = {(time_t)dt, (long)((dt - floor(dt)) * 1e9)};
    *ready = 0;
    int r = ppoll(pf, fd2 >= 0 ? 2 : 1, &ts, NULL);
    if (r < 0 && errno != EINTR)
        return core_err_set(err, -1, "station: poll: %s", strerror(errno));
    if (r <= 0)
        return 0;
    if (pf[0].revents & POLLIN)
        sim_station_handle(st);
    *ready = fd2 >= 0 && (pf[1].revents & (POLLIN | POLLHUP | POLLERR));
    return 0;
}

/* The keys pending on fd at t_s into c: 1 on a quit key or the end of the
 * input, 0, or -1 with err. */
static int read_keys(int fd, sim_station_keys *keys, double t_s, sim_station_controls *c, core_err *err)
{
    unsigned char kb[64];
    ssize_t n = read(fd, kb, sizeof kb);
    if (n == 0 || (n < 0 && errno == EIO)) /* the terminal hung up */
        return 1;
    if (n < 0 && errno != EINTR && errno != EAGAIN)
        return core_err_set(err, -1, "station: reading keys: %s", strerror(errno));
    for (ssize_t i = 0; i < n; i++)
        if (sim_station_keys_feed(keys, kb[i], t_s, c) == SIM_KEY_QUIT)
            return 1;
    return 0;
}

/* Before the first message: until a heli_state_t brings the flown
 * controls: 0 (have them), 1 (stopped, or q), or -1 with err (none within
 * wait_s). The keys are read only for q. */
static int wait_flown(sim_station *st, const sim_station_run_opts *o, core_err *err)
{
    sim_station_view *v = &st->v;
    const double t0 = core_monotonic_s(), end = t0 + o->wait_s;
    const double show_period = o->show_hz > 0.0 ? 1.0 / o->show_hz : INFINITY;
    double next_show = t0;
    v->waiting = 1;
    while (!v->have_heli) {
        if (o->stop && *o->stop)
            return 1;
        double now = core_monotonic_s();
        if (now >= end)
            return core_err_set(err, -1,
                                "no %s on %s within %g s: the station sends nothing before it has the controls the "
                                "loop flies (is disim fly running, with --lcm the same URL?)",
                                "heli_state_t", DISIM_CH_HELI_STATE, o->wait_s);
        if (o->show && now >= next_show) {
            o->show(o->user, v);
            next_show = now + show_period;
        }
        int ready;
        if (station_poll(st, o->key_fd, fmin(end, next_show), &ready, err) != 0)
            return -1;
        if (ready) {
            sim_station_keys k0;
            sim_station_controls c0;
            sim_station_keys_init(&k0, 0.0, NULL, 0.0);
            sim_station_controls_centre(&c0);
            int r = read_keys(o->key_fd, &k0, 0.0, &c0, err);
            if (r != 0)
                return r;
        }
    }
    v->waiting = 0;
    return 0;
}

/* The sources at the reference (the flown controls): c, and the view's
 * reference. */
/* A script flown as a stick: the collective a lever, the rest
 * spring-centred (sim_station_trim). */
static void script_axes(sim_station_axes *a)
{
    memset(a, 0, sizeof *a);
    a->axis[SIM_AXIS_COLLECTIVE].lever = 1;
    a->trim_button_code = a->trim_release_code = a->take_over_code = -1;
}

static void start_sources(sim_station *st, const sim_station_run_opts *o, const sim_station_controls *pos,
                          sim_station_trim *trim, sim_station_controls *c)
{
    sim_station_view *v = &st->v;
    hfm_controls ref = {.collective_pct = v->heli_ctl_pct[0],
                        .long_cyclic_pct = v->heli_ctl_pct[1],
                        .lat_cyclic_pct = v->heli_ctl_pct[2],
                        .pedal_pct = v->heli_ctl_pct[3]};
    *c = *pos;
    c->ctl = ref;
    c->take_over = 0;
    if (o->keys)
        sim_station_keys_init(o->keys, o->keys->rate_pct_s, &ref, 0.0);
    if (o->dev) {
        sim_station_trim_init(trim, o->authority_pct, sim_station_evdev_axes(o->dev), v->heli_ctl_pct, pos);
        sim_station_trim_apply(trim, pos, c);
    }
    if (o->script && !o->script_absolute) {
        sim_station_axes axes;
        script_axes(&axes);
        sim_station_controls sp;
        memset(&sp, 0, sizeof sp);
        sim_station_script_at(o->script, 0.0, &sp);
        sim_station_trim_init(trim, o->authority_pct, &axes, v->heli_ctl_pct, &sp);
        sim_station_trim_apply(trim, &sp, c);
    }
    if (o->keys || o->dev || (o->script && !o->script_absolute)) {
        v->have_ref = 1;
        memcpy(v->ref_pct, v->heli_ctl_pct, sizeof v->ref_pct);
    }
}

int sim_station_run(sim_station *st, const sim_station_run_opts *o, core_err *err)
{
    if (!(o->rate_hz >= 1.0 && o->rate_hz <= 1000.0))
        return core_err_set(err, -1, "station: rate %g Hz: expected 1 to 1000", o->rate_hz);
    if (!(o->wait_s > 0.0))
        return core_err_set(err, -1, "station: wait %g s for the flown controls: expected more than 0", o->wait_s);
    int nsrc = (o->script != NULL) + (o->dev != NULL) + (o->key_fd >= 0);
    if (nsrc != 1 || (o->key_fd >= 0 && !o->keys))
        return core_err_set(err, -1, "station: expected exactly one source (script, device or keys)");
    if ((o->dev || (o->script && !o->script_absolute)) && !(o->authority_pct > 0.0 && o->authority_pct <= 100.0))
        return core_err_set(err, -1, "station: authority %g %%: expected more than 0, at most 100", o->authority_pct);
    int w = wait_flown(st, o, err);
    if (w != 0)
        return w > 0 ? 0 : -1;
    sim_station_controls c, pos = o->start;
    sim_station_trim trim;
    if (o->dev && sim_station_evdev_read(o->dev, &pos, err) != 0) /* where the sticks are now */
        return -1;
    start_sources(st, o, &pos, &trim, &c);
    const double period = 1.0 / o->rate_hz;
    const double t0 = core_monotonic_s();
    const double end = o->duration_s > 0.0 ? t0 + o->duration_s : INFINITY;
    const double show_period = o->show_hz > 0.0 ? 1.0 / o->show_hz : INFINITY;
    double next_show = t0 + show_period;
    long k = 0; /* the next deadline is t0 + k period */
    sim_station_view *v = &st->v;
    int fd2 = o->dev ? sim_station_evdev_fd(o->dev) : o->key_fd;
    for (;;) {
        if (o->stop && *o->stop)
            return 0;
        double now = core_monotonic_s();
        if (now >= end)
            return 0;
        if (now >= t0 + (double)k * period) {
            double t = now - t0;
            if (o->script && o->script_absolute)
                sim_station_script_at(o->script, t, &c);
            else if (o->script) {
                sim_station_controls sp;
                memset(&sp, 0, sizeof sp);
                sim_station_script_at(o->script, t, &sp);
                sim_station_trim_apply(&trim, &sp, &c);
                memcpy(v->ref_pct, trim.ref_pct, sizeof v->ref_pct);
            }
            if (o->keys)
                sim_station_keys_advance(o->keys, t, &c);
            if (o->take_over)
                c.take_over = 1;
            if (sim_station_publish(st, (int64_t)llround(t * 1e6), &c, err) != 0)
                return -1;
            if (o->keys)
                c.take_over = 0; /* the key asks once */
            long next = (long)floor(t / period) + 1; /* deadlines already passed are skipped */
            if (next <= k)
                next = k + 1; /* t / period rounded below k */
            v->late += next - k - 1;
            k = next;
        }
        if (o->show && now >= next_show) {
            o->show(o->user, v);
            next_show += show_period * floor((now - next_show) / show_period + 1.0);
        }
        double wake = fmin(fmin(t0 + (double)k * period, next_show), end);
        int ready;
        if (station_poll(st, fd2, wake, &ready, err) != 0)
            return -1;
        if (ready && o->dev) {
            if (sim_station_evdev_read(o->dev, &pos, err) != 0)
                return -1;
            sim_station_trim_apply(&trim, &pos, &c);
            memcpy(v->ref_pct, trim.ref_pct, sizeof v->ref_pct);
        }
        if (ready && o->keys) {
            int r = read_keys(o->key_fd, o->keys, core_monotonic_s() - t0, &c, err);
            if (r != 0)
                return r > 0 ? 0 : -1;
        }
    }
}
