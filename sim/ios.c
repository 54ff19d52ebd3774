/* ios.c -- the instructor's console (disim ios): an instructor at a
 * terminal beside the pilot, as at X-Plane's instructor station or
 * FLIGHTLAB's, freezes and runs the flight, resets it to the hover or the
 * deck, repositions it relative to the landing spot, sets the WOD, the
 * sea state and the turbulence, and takes and restores snapshots.
 *
 * Each typed line (sim_ios_parse) becomes one sim_control_t on
 * DISIM_SIM_CONTROL (sim_ios_send) with a seq of its own, the wall clock's
 * microseconds (rising within a process, apart across consoles started one
 * after the other), and the console waits for the sim_status_t whose
 * control_seq is that seq: the flight loop (sim/loop.c) publishes one
 * after every control it carries out or refuses, with the reason. A status
 * is checked (disim_lcm_check_raw, an older disim's read as the newest by
 * disim_lcm_upgrade) before it is decoded. Units as typed: knots and
 * degrees for the WOD and headings, metres in S for positions; sent in SI.
 */
#include "sim.h"
#include "disim_lcm.h"

#include <lcm/lcm.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* ------------------------------------------------------------ parsing */
const char *sim_ios_help(void)
{
    return "freeze | pause                 freeze the flight\n"
           "resume | unfreeze              run it again\n"
           "reset                          the scenario again, as the command line had it\n"
           "reset hover                    the trimmed hover at the scenario's station\n"
           "reset deck [HDG_DEG]           standing on the deck, heading from the bow (0)\n"
           "reposition X Y Z [HDG_DEG]     the trimmed hover with the CG at X Y Z m from the spot\n"
           "                               (S: x bow, y starboard, z down; the heading 0)\n"
           "wod KT DIR_DEG                 the wind over the deck, from DIR relative to the bow\n"
           "sea N                          the sea state, 0 to 6\n"
           "turb on|off                    the turbulence\n"
           "snap NAME                      keep the flight's state as NAME\n"
           "restore NAME                   fly on from the state kept as NAME\n"
           "load SCENARIO                  fly another scenario\n"
           "status                         the loop's next status\n"
           "wait S                         wait S seconds (scripts)\n"
           "help, quit\n";
}

/* The words of a line, at most max; their count. */
static int split(char *s, char **w, int max)
{
    int n = 0;
    for (char *tok = strtok(s, " \t\r\n"); tok && n < max; tok = strtok(NULL, " \t\r\n"))
        w[n++] = tok;
    return n;
}

static int num(const char *s, double *v)
{
    char *end;
    *v = strtod(s, &end);
    return end != s && *end == '\0';
}

static int need(int n, int lo, int hi, const char *what, core_err *err)
{
    if (n < lo || n > hi)
        return core_err_set(err, -1, "expected '%s'", what);
    return 0;
}

/* The numbers w[0..n) into v (n of them): 0, or -1 with err. */
static int nums(char **w, int n, double *v, const char *what, core_err *err)
{
    for (int i = 0; i < n; i++)
        if (!num(w[i], &v[i]))
            return core_err_set(err, -1, "'%s' is not a number: expected '%s'", w[i], what);
    return 0;
}

static int parse_reset(char **w, int n, sim_ios_cmd *c, core_err *err)
{
    if (n == 1) {
        c->command = DISIM_SIM_CONTROL_T_RESET;
        return 0;
    }
    if (!strcmp(w[1], "hover") && n == 2) {
        c->command = DISIM_SIM_CONTROL_T_RESET_HOVER;
        return 0;
    }
    if (!strcmp(w[1], "deck") && n <= 3) {
        double h = 0.0;
        if (n == 3 && nums(w + 2, 1, &h, "reset deck [HDG_DEG]", err) != 0)
            return -1;
        c->command = DISIM_SIM_CONTROL_T_RESET_DECK;
        c->heading_rad = h * CORE_DEG_TO_RAD;
        return 0;
    }
    return core_err_set(err, -1, "expected 'reset', 'reset hover' or 'reset deck [HDG_DEG]'");
}

static int parse_name(char **w, int n, int command, sim_ios_cmd *c, core_err *err)
{
    if (need(n, 2, 2, command == DISIM_SIM_CONTROL_T_SNAPSHOT ? "snap NAME" : "restore NAME", err) != 0)
        return -1;
    if (strlen(w[1]) >= sizeof c->name)
        return core_err_set(err, -1, "'%s': a name of at most %zu characters", w[1], sizeof c->name - 1);
    c->command = command;
    snprintf(c->name, sizeof c->name, "%s", w[1]);
    return 0;
}

/* The commands with numbers: 0, 1 not one of them, -1 with err. */
static int parse_numbers(char **w, int n, sim_ios_cmd *c, core_err *err)
{
    double v[4];
    if (!strcmp(w[0], "reposition")) {
        const char *u = "reposition X Y Z [HDG_DEG]";
        if (need(n, 4, 5, u, err) != 0 || nums(w + 1, n - 1, v, u, err) != 0)
            return -1;
        c->command = DISIM_SIM_CONTROL_T_REPOSITION;
        memcpy(c->pos_S_m, v, sizeof c->pos_S_m);
        c->heading_rad = n == 5 ? v[3] * CORE_DEG_TO_RAD : NAN;
    } else if (!strcmp(w[0], "wod")) {
        if (need(n, 3, 3, "wod KT DIR_DEG", err) != 0 || nums(w + 1, 2, v, "wod KT DIR_DEG", err) != 0)
            return -1;
        c->command = DISIM_SIM_CONTROL_T_SET_WOD;
        c->wod_speed_mps = v[0] * CORE_KT_TO_MPS;
        c->wod_dir_rad = v[1] * CORE_DEG_TO_RAD;
    } else if (!strcmp(w[0], "sea")) {
        if (need(n, 2, 2, "sea N", err) != 0 || nums(w + 1, 1, v, "sea N", err) != 0)
            return -1;
        if (v[0] != floor(v[0]) || fabs(v[0]) > 100.0)
            return core_err_set(err, -1, "sea %s: expected a whole number (0 to 6)", w[1]);
        c->command = DISIM_SIM_CONTROL_T_SET_SEA;
        c->sea_state = (int)v[0];
    } else if (!strcmp(w[0], "wait")) {
        if (need(n, 2, 2, "wait S", err) != 0 || nums(w + 1, 1, v, "wait S", err) != 0)
            return -1;
        if (!(v[0] >= 0.0 && v[0] <= 3600.0))
            return core_err_set(err, -1, "wait %s: expected 0 to 3600 s", w[1]);
        c->command = SIM_IOS_WAIT;
        c->wait_s = v[0];
    } else
        return 1;
    return 0;
}

int sim_ios_parse(const char *line, sim_ios_cmd *c, core_err *err)
{
    memset(c, 0, sizeof *c);
    c->heading_rad = NAN;
    c->command = SIM_IOS_NONE;
    char buf[1024], *w[8];
    if (strlen(line) >= sizeof buf)
        return core_err_set(err, -1, "a line of at most %zu characters", sizeof buf - 1);
    snprintf(buf, sizeof buf, "%s", line);
    char *hash = strchr(buf, '#');
    if (hash)
        *hash = '\0';
    int n = split(buf, w, 8);
    if (n == 0)
        return 0;
    static const struct {
        const char *word;
        int command;
    } plain[] = {{"freeze", DISIM_SIM_CONTROL_T_PAUSE}, {"pause", DISIM_SIM_CONTROL_T_PAUSE},
                 {"resume", DISIM_SIM_CONTROL_T_RESUME}, {"unfreeze", DISIM_SIM_CONTROL_T_RESUME},
                 {"status", SIM_IOS_STATUS}, {"help", SIM_IOS_HELP}, {"quit", SIM_IOS_QUIT}, {"exit", SIM_IOS_QUIT}};
    for (size_t i = 0; i < sizeof plain / sizeof plain[0]; i++)
        if (!strcmp(w[0], plain[i].word)) {
            if (n != 1)
                return core_err_set(err, -1, "'%s' takes nothing more", w[0]);
            c->command = plain[i].command;
            return 0;
        }
    if (!strcmp(w[0], "reset"))
        return parse_reset(w, n, c, err);
    if (!strcmp(w[0], "snap") || !strcmp(w[0], "snapshot"))
        return parse_name(w, n, DISIM_SIM_CONTROL_T_SNAPSHOT, c, err);
    if (!strcmp(w[0], "restore"))
        return parse_name(w, n, DISIM_SIM_CONTROL_T_RESTORE, c, err);
    if (!strcmp(w[0], "turb")) {
        if (n != 2 || (strcmp(w[1], "on") && strcmp(w[1], "off")))
            return core_err_set(err, -1, "expected 'turb on' or 'turb off'");
        c->command = DISIM_SIM_CONTROL_T_SET_TURBULENCE;
        c->turbulence = !strcmp(w[1], "on");
        return 0;
    }
    if (!strcmp(w[0], "load")) {
        if (need(n, 2, 2, "load SCENARIO", err) != 0)
            return -1;
        if (strlen(w[1]) >= sizeof c->path)
            return core_err_set(err, -1, "load: the path is too long");
        c->command = DISIM_SIM_CONTROL_T_LOAD_SCENARIO;
        snprintf(c->path, sizeof c->path, "%s", w[1]);
        return 0;
    }
    int r = parse_numbers(w, n, c, err);
    if (r <= 0)
        return r;
    return core_err_set(err, -1, "'%s': not a command (try 'help')", w[0]);
}

const char *sim_ios_command_name(int command)
{
    static const char *const names[] = {"pause", "resume", "reset", "load scenario", "reset hover", "reset deck",
                                        "reposition", "set wod", "set sea", "set turbulence", "snapshot", "restore"};
    int i = command - DISIM_SIM_CONTROL_T_PAUSE;
    return i >= 0 && i < (int)(sizeof names / sizeof names[0]) ? names[i] : "?";
}

/* ---------------------------------------------------------------- LCM */
struct sim_ios {
    lcm_t *lc;
    lcm_subscription_t *sub;
    long long last_seq;
    int have;          /* a status arrived since the last take */
    sim_ios_answer st; /* the newest status */
};

static double wall_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void take_status(sim_ios *io, const disim_sim_status_t *m)
{
    sim_ios_answer *a = &io->st;
    memset(a, 0, sizeof *a);
    a->seq = m->control_seq;
    a->command = m->control_command;
    a->result = m->control_result;
    /* text from the network, shown on a terminal: escaped */
    core_escape(m->control_message, a->message, sizeof a->message);
    a->apply_s = m->control_apply_s;
    a->state = m->state;
    a->sim_time_s = m->sim_time_s;
    a->rate_hz = m->rate_hz;
    a->real_time_factor = m->real_time_factor;
    core_escape(m->scenario, a->scenario, sizeof a->scenario);
    a->flags = (unsigned)m->flags;
    a->n_stations = m->n_stations;
    if (m->active_station >= 0 && m->active_station < m->n_stations)
        core_escape(m->station_ids[m->active_station], a->active_id, sizeof a->active_id);
    a->control_refused = m->control_refused;
    io->have = 1;
}

static void on_status(const lcm_recv_buf_t *rb, const char *channel, void *user)
{
    (void)channel;
    sim_ios *io = user;
    const void *data = rb->data;
    int size = (int)rb->data_size;
    unsigned char *up = malloc((size_t)size + 64);
    if (!up)
        return;
    int un = disim_lcm_upgrade("sim_status_t", data, size, up, size + 64);
    if (un > 0)
        data = up, size = un;
    disim_sim_status_t m;
    if (disim_lcm_check_raw("sim_status_t", data, size, NULL, 0) == 0 &&
        disim_sim_status_t_decode(data, 0, size, &m) == size) {
        take_status(io, &m);
        disim_sim_status_t_decode_cleanup(&m);
    }
    free(up);
}

sim_ios *sim_ios_create(const char *lcm_url, core_err *err)
{
    sim_ios *io = calloc(1, sizeof *io);
    if (!io) {
        core_err_set(err, -1, "ios: out of memory");
        return NULL;
    }
    if (!(io->lc = lcm_create(disim_lcm_url(lcm_url))) || !(io->sub = lcm_subscribe(io->lc, DISIM_CH_SIM_STATUS, on_status, io))) {
        core_err_set(err, -1, "LCM: cannot open '%s'", lcm_url ? lcm_url : "the default URL");
        sim_ios_destroy(io);
        return NULL;
    }
    return io;
}

void sim_ios_destroy(sim_ios *io)
{
    if (!io)
        return;
    if (io->lc) {
        if (io->sub)
            lcm_unsubscribe(io->lc, io->sub);
        lcm_destroy(io->lc);
    }
    free(io);
}

/* Statuses handled until one answers seq (seq < 0: any status), or
 * timeout_s: 0, or -1. */
static int wait_for(sim_ios *io, long long seq, double timeout_s)
{
    double end = wall_s() + timeout_s;
    for (;;) {
        if (io->have && (seq < 0 || io->st.seq == seq))
            return 0;
        double left = end - wall_s();
        if (left <= 0.0)
            return -1;
        int ms = (int)ceil(fmin(left, 0.1) * 1000.0);
        if (lcm_handle_timeout(io->lc, ms) < 0)
            return -1;
    }
}

int sim_ios_send(sim_ios *io, const sim_ios_cmd *cmd, double timeout_s, sim_ios_answer *a, core_err *err)
{
    if (cmd->command < DISIM_SIM_CONTROL_T_PAUSE || cmd->command > DISIM_SIM_CONTROL_T_RESTORE)
        return core_err_set(err, -1, "ios: %d is not a control", cmd->command);
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    long long seq = (long long)ts.tv_sec * 1000000LL + ts.tv_nsec / 1000;
    if (seq <= io->last_seq)
        seq = io->last_seq + 1;
    io->last_seq = seq;
    disim_sim_control_t m;
    memset(&m, 0, sizeof m);
    m.seq = seq;
    m.command = (int8_t)cmd->command;
    m.scenario_path = (char *)cmd->path;
    memcpy(m.pos_S_m, cmd->pos_S_m, sizeof m.pos_S_m);
    m.heading_rad = cmd->heading_rad;
    m.wod_speed_mps = cmd->wod_speed_mps;
    m.wod_dir_rad = cmd->wod_dir_rad;
    m.sea_state = (int8_t)(cmd->sea_state < -128 ? -128 : cmd->sea_state > 127 ? 127 : cmd->sea_state);
    m.turbulence = (int8_t)cmd->turbulence;
    m.name = (char *)cmd->name;
    io->have = 0;
    if (disim_sim_control_t_publish(io->lc, DISIM_CH_SIM_CONTROL, &m) != 0)
        return core_err_set(err, -1, "LCM: cannot publish on %s", DISIM_CH_SIM_CONTROL);
    if (wait_for(io, seq, timeout_s) != 0)
        return core_err_set(err, -1, "no answer within %.1f s (is disim fly running on this LCM URL?)", timeout_s);
    *a = io->st;
    return a->result == DISIM_SIM_STATUS_T_CONTROL_ACCEPTED ? 0 : 1;
}

int sim_ios_status(sim_ios *io, double timeout_s, sim_ios_answer *a, core_err *err)
{
    io->have = 0;
    if (wait_for(io, -1, timeout_s) != 0)
        return core_err_set(err, -1, "no status within %.1f s (is disim fly running on this LCM URL?)", timeout_s);
    *a = io->st;
    return 0;
}

void sim_ios_format(const sim_ios_answer *a, int status, char *buf, size_t n)
{
    static const char *states[] = {"running", "frozen", "stopped"};
    const char *state = a->state >= 0 && a->state <= 2 ? states[a->state] : "?";
    if (!status) {
        snprintf(buf, n, "%s: %s (%.3f s)", a->result == DISIM_SIM_STATUS_T_CONTROL_ACCEPTED ? "ok" : "refused",
                 a->message, a->apply_s);
        return;
    }
    snprintf(buf, n, "%s %s at t = %.2f s, %.1fx real time, %s%s%s%s, station %s; last control: %s '%s'",
             a->scenario, state, a->sim_time_s, a->real_time_factor,
             a->flags & DISIM_SIM_STATUS_T_FLAG_ON_DECK ? "on deck" : "airborne",
             a->flags & DISIM_SIM_STATUS_T_FLAG_INPUT_HELD ? ", input held" : "",
             a->flags & DISIM_SIM_STATUS_T_FLAG_CRASH ? ", crashed" : "",
             a->flags & DISIM_SIM_STATUS_T_FLAG_REPLAY ? ", replay" : "", a->active_id[0] ? a->active_id : "none",
             a->result == DISIM_SIM_STATUS_T_CONTROL_ACCEPTED ? "accepted"
             : a->result == DISIM_SIM_STATUS_T_CONTROL_REFUSED ? "refused"
                                                               : "none",
             a->message);
}
