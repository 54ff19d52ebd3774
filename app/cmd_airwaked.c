/* cmd_airwaked.c -- `disim airwaked DB_DIR [--jobs N] [--ships DIR]
 * [--max-iter N] [--exit-when-idle] [--no-lcm] [--engine E] [--np N]
 * [--aircraft DIR]`: the background airwake
 * builder. It serves the database's queue (filled by `disim airwake --queue`,
 * `disim shol` and other processes) and LCM requests on DISIM_AIRWAKE_REQUEST,
 * and publishes DISIM_AIRWAKE_STATUS. Progress goes to a terminal as one
 * updating line; in a log (not a terminal) only state changes are written. */
#include "awdb.h"
#include "cmds.h"
#include "foam.h"
#include "disim_lcm.h"

#include <lcm/lcm.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <unistd.h>

static volatile sig_atomic_t stop_flag = 0;
static void on_signal(int sig)
{
    (void)sig;
    stop_flag = 1;
}

/* builds in progress, for the terminal line's rate and time left */
#define TTY_SLOTS 32
typedef struct tty_slot {
    char name[200];
    double t0_s;
    int it0;
} tty_slot;

typedef struct daemon_ctx {
    awdb *db;
    lcm_t *lc;
    int64_t seq;
    int tty;
    const core_log *log;
    pthread_mutex_t mu; /* the builder's jobs report from their threads */
    tty_slot slot[TTY_SLOTS];
} daemon_ctx;

static int64_t now_us(void)
{
    struct timeval tv;
    gettimeofday(&tv, NULL);
    return (int64_t)tv.tv_sec * 1000000 + tv.tv_usec;
}

static void publish_status(daemon_ctx *c, const awdb_key *k, const char *request_id, int8_t state,
                           double frac, double res, int it, const char *path, const char *msg)
{
    if (!c->lc)
        return;
    disim_airwake_status_t m;
    memset(&m, 0, sizeof m);
    char name[200];
    awdb_key_name(k, name, sizeof name);
    m.utime = now_us();
    m.seq = c->seq++;
    m.request_id = (char *)(request_id ? request_id : name);
    m.ship = (char *)k->ship;
    m.aircraft = (char *)k->aircraft;
    m.wod_speed_mps = k->wod_speed_mps;
    m.wod_dir_rad = k->wod_dir_rad;
    m.state = state;
    m.progress = frac;
    m.residual = res;
    m.iterations = it;
    m.path = (char *)(path ? path : "");
    m.message = (char *)(msg ? msg : "");
    disim_airwake_status_t_publish(c->lc, DISIM_CH_AIRWAKE_STATUS, &m);
}

static double now_s(void) { return 1e-6 * (double)now_us(); }

/* The slot of a build by name (a free one when new, with its start), or
 * NULL when all are taken; remove: free it. Called under c->mu. */
static tty_slot *tty_slot_of(daemon_ctx *c, const char *name, int it, int remove)
{
    tty_slot *free_slot = NULL;
    for (int i = 0; i < TTY_SLOTS; i++) {
        tty_slot *t = &c->slot[i];
        if (t->name[0] && !strcmp(t->name, name)) {
            if (remove)
                t->name[0] = '\0';
            return t;
        }
        if (!t->name[0] && !free_slot)
            free_slot = t;
    }
    if (remove || !free_slot)
        return NULL;
    snprintf(free_slot->name, sizeof free_slot->name, "%s", name);
    free_slot->t0_s = now_s();
    free_slot->it0 = it;
    return free_slot;
}

static void on_status(void *user, const awdb_key *k, awdb_state s, double frac, double res, int it,
                      const char *path, const char *msg)
{
    daemon_ctx *c = user;
    static const int8_t map[] = {DISIM_AIRWAKE_STATUS_T_QUEUED, DISIM_AIRWAKE_STATUS_T_QUEUED,
                                 DISIM_AIRWAKE_STATUS_T_RUNNING, DISIM_AIRWAKE_STATUS_T_READY,
                                 DISIM_AIRWAKE_STATUS_T_FAILED};
    publish_status(c, k, NULL, map[s], frac, res, it, path, msg);
    char name[200];
    awdb_key_name(k, name, sizeof name);
    pthread_mutex_lock(&c->mu);
    if (s == AWDB_RUNNING && frac > 0.0) {
        /* on a terminal only (a log gets state changes only), an updating
         * line: percent of the iteration cap, iterations per second since
         * this build's first report, and the time left at that rate (an
         * upper bound: a field can stop at convergence) */
        if (c->tty) {
            tty_slot *t = tty_slot_of(c, name, it, 0);
            double el = t ? now_s() - t->t0_s : 0.0, rate = t && el > 0.0 ? (it - t->it0) / el : 0.0;
            double left = rate > 0.0 ? (it / frac - it) / rate : 0.0;
            if (rate > 0.0)
                fprintf(stderr, "\r  %-48.48s %5.1f%%  residual %.2e  iteration %d  %.2f it/s  at most %.0f %s left   ",
                        name, 100.0 * frac, res, it, rate, left < 120.0 ? left : left / 60.0,
                        left < 120.0 ? "s" : "min");
            else
                fprintf(stderr, "\r  %-48.48s %5.1f%%  residual %.2e  iteration %d   ", name, 100.0 * frac, res, it);
        }
    } else {
        if (s != AWDB_RUNNING)
            tty_slot_of(c, name, 0, 1);
        fprintf(stderr, "%sairwaked: %s %s%s%s\n", c->tty ? "\r" : "", awdb_state_name(s), name,
                msg && msg[0] ? ": " : "", msg ? msg : "");
    }
    pthread_mutex_unlock(&c->mu);
}

static void on_request(daemon_ctx *c, const disim_airwake_request_t *m)
{
    char err[256];
    awdb_key k;
    memset(&k, 0, sizeof k);
    if (disim_lcm_check_airwake_request(m, err, sizeof err) != 0) {
        core_log_msg(c->log, CORE_LOG_WARN, "refused LCM request: %s", err);
        snprintf(k.ship, sizeof k.ship, "%s", m->ship ? m->ship : "");
        publish_status(c, &k, m->request_id, DISIM_AIRWAKE_STATUS_T_FAILED, 0, 0, 0, "", err);
        return;
    }
    /* What the message cannot say is refused, not approximated: the blade
     * loads of a loaded disk have no field in it (a uniform disk built in
     * its place would be announced READY for the loaded request), and a
     * name cut to fit the key would be another ship's or aircraft's. */
    const char *bad = NULL;
    /* the name lengths in the messages below are the key's buffers less the NUL */
    _Static_assert(sizeof(((awdb_key *)0)->ship) == 96 && sizeof(((awdb_key *)0)->aircraft) == 64,
                   "update the name lengths in the messages below");
    if (m->rotor == DISIM_AIRWAKE_REQUEST_T_ROTOR_LOADED)
        bad = "airwake_request_t.rotor = 2 (loaded): expected 0 (off) or 1 (uniform); the message carries no "
              "blade-load table (queue loaded-disk fields with disim shol or disim airwake --queue)";
    else if (strlen(m->ship) >= sizeof k.ship)
        bad = "airwake_request_t.ship: expected a name of at most 95 characters";
    else if (strlen(m->aircraft) >= sizeof k.aircraft)
        bad = "airwake_request_t.aircraft: expected a name of at most 63 characters";
    if (bad) {
        core_log_msg(c->log, CORE_LOG_WARN, "refused LCM request %s: %s", m->request_id, bad);
        snprintf(k.ship, sizeof k.ship, "%.*s", (int)sizeof k.ship - 1, m->ship);
        publish_status(c, &k, m->request_id, DISIM_AIRWAKE_STATUS_T_FAILED, 0, 0, 0, "", bad);
        return;
    }
    snprintf(k.ship, sizeof k.ship, "%s", m->ship);
    snprintf(k.aircraft, sizeof k.aircraft, "%s", m->aircraft);
    k.wod_speed_mps = m->wod_speed_mps;
    k.wod_dir_rad = m->wod_dir_rad;
    k.rotor = m->rotor == DISIM_AIRWAKE_REQUEST_T_ROTOR_OFF ? CORE_ROTOR_OFF : CORE_ROTOR_UNIFORM;
    k.thrust_N = m->rotor_thrust_N;
    memcpy(k.station_S_m, m->station_S_m, sizeof k.station_S_m);
    k.radius_m = m->rotor_radius_m;
    k.shaft_pitch_rad = m->shaft_pitch_rad;
    k.shaft_roll_rad = m->shaft_roll_rad;
    k.grid = core_grid_parse(m->grid); /* one of the three: lcm_types checked the message */
    core_err e = {0};
    awdb_state before;
    if (awdb_submit(c->db, &k, &before, &e) != 0) {
        core_log_msg(c->log, CORE_LOG_WARN, "refused LCM request %s: %s", m->request_id, e.msg);
        publish_status(c, &k, m->request_id, DISIM_AIRWAKE_STATUS_T_FAILED, 0, 0, 0, "", e.msg);
        return;
    }
    char path[1024] = "";
    awdb_state now = awdb_query(c->db, &k, path, sizeof path);
    publish_status(c, &k, m->request_id,
                   now == AWDB_READY ? DISIM_AIRWAKE_STATUS_T_READY
                   : now == AWDB_RUNNING ? DISIM_AIRWAKE_STATUS_T_RUNNING
                                          : DISIM_AIRWAKE_STATUS_T_QUEUED,
                   now == AWDB_READY ? 1.0 : 0.0, 0, 0, path, "");
}


/* The raw message, checked before lcm-gen's decoder sees it: lcm 1.3.1
 * would decode a string without its NUL, and strlen on it would run past
 * the buffer. A refused message gets a FAILED status without a request id
 * (it cannot be read safely). */
static void on_request_raw(const lcm_recv_buf_t *rb, const char *ch, void *user)
{
    (void)ch;
    daemon_ctx *c = user;
    char err[256];
    awdb_key k;
    memset(&k, 0, sizeof k);
    if (disim_lcm_check_raw("airwake_request_t", rb->data, (int)rb->data_size, err, sizeof err) != 0) {
        core_log_msg(c->log, CORE_LOG_WARN, "refused LCM request: %s", err);
        publish_status(c, &k, "", DISIM_AIRWAKE_STATUS_T_FAILED, 0, 0, 0, "", err);
        return;
    }
    disim_airwake_request_t m;
    memset(&m, 0, sizeof m);
    if (disim_airwake_request_t_decode(rb->data, 0, (int)rb->data_size, &m) < 0) {
        const char *why = "airwake_request_t: cannot decode (another type's fingerprint?)";
        core_log_msg(c->log, CORE_LOG_WARN, "refused LCM request: %s", why);
        publish_status(c, &k, "", DISIM_AIRWAKE_STATUS_T_FAILED, 0, 0, 0, "", why);
    } else {
        on_request(c, &m);
    }
    disim_airwake_request_t_decode_cleanup(&m);
}

static void on_idle(void *user)
{
    daemon_ctx *c = user;
    if (c->lc)
        while (lcm_handle_timeout(c->lc, 0) > 0)
            ;
}

/* The command line of disim airwaked. */
typedef struct airwaked_args {
    const char *dir, *ships, *aircraft, *hostfile, *work_dir;
    long jobs, max_iter;
    int once, use_lcm;
    int openfoam;   /* --engine openfoam */
    long np;        /* --np: its MPI ranks (0: 2) */
    int jobs_given; /* --jobs given (else, with OpenFOAM, the cores over its ranks) */
    int aircraft_given;
} airwaked_args;

/* The flags into o: 0, or 2 (usage) after the message. */
static int airwaked_parse(int argc, char **argv, airwaked_args *o)
{
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if ((!strcmp(a, "--jobs") || !strcmp(a, "--ships") || !strcmp(a, "--max-iter") || !strcmp(a, "--engine") ||
             !strcmp(a, "--np") || !strcmp(a, "--aircraft") || !strcmp(a, "--hostfile") ||
             !strcmp(a, "--work-dir")) &&
            i + 1 >= argc) {
            fprintf(stderr, "disim airwaked: %s: expected a value\n", a);
            return 2;
        }
        if (!strcmp(a, "--jobs")) {
            char *end;
            o->jobs = strtol(argv[++i], &end, 10);
            o->jobs_given = 1;
            if (*end || o->jobs < 1 || o->jobs > 64) {
                fprintf(stderr, "disim airwaked: --jobs '%s': expected 1 to 64\n", argv[i]);
                return 2;
            }
        } else if (!strcmp(a, "--max-iter")) {
            char *end;
            o->max_iter = strtol(argv[++i], &end, 10);
            if (*end || o->max_iter < 10) {
                fprintf(stderr, "disim airwaked: --max-iter '%s': expected an integer >= 10\n", argv[i]);
                return 2;
            }
        } else if (!strcmp(a, "--np")) {
            char *end;
            o->np = strtol(argv[++i], &end, 10);
            if (*end || o->np < 1 || o->np > 4096) {
                fprintf(stderr, "disim airwaked: --np '%s': expected 1 to 4096\n", argv[i]);
                return 2;
            }
        } else if (!strcmp(a, "--engine")) {
            const char *v = argv[++i];
            if (strcmp(v, "embedded") && strcmp(v, "openfoam")) {
                fprintf(stderr, "disim airwaked: --engine '%s': expected embedded or openfoam\n", v);
                return 2;
            }
            o->openfoam = !strcmp(v, "openfoam");
        } else if (!strcmp(a, "--ships"))
            o->ships = argv[++i];
        else if (!strcmp(a, "--hostfile"))
            o->hostfile = argv[++i];
        else if (!strcmp(a, "--work-dir"))
            o->work_dir = argv[++i];
        else if (!strcmp(a, "--aircraft")) {
            o->aircraft = argv[++i];
            o->aircraft_given = 1;
        }
        else if (!strcmp(a, "--exit-when-idle"))
            o->once = 1;
        else if (!strcmp(a, "--no-lcm"))
            o->use_lcm = 0;
        else if (a[0] == '-') {
            fprintf(stderr, "disim airwaked: unknown flag '%s'\n", a);
            return 2;
        } else if (!o->dir)
            o->dir = a;
        else {
            fprintf(stderr, "disim airwaked: unexpected argument '%s'\n", a);
            return 2;
        }
    }
    if (!o->dir) {
        fprintf(stderr, "usage: disim airwaked DB_DIR [--jobs N] [--ships DIR] [--max-iter N] "
                        "[--exit-when-idle] [--no-lcm] [--engine embedded|openfoam] [--np N] [--aircraft DIR]\n"
                        "       [--hostfile FILE] [--work-dir DIR]\n"
                        "  --engine openfoam: build with OpenFOAM (mpirun -np N, 2 by default), into a database\n"
                        "       of its own (DB_DIR/engine names it; docs/openfoam.md); the loaded rotor\n"
                        "       as rotorDisk with the blades of the key's aircraft, found in --aircraft DIR\n"
                        "       (scenarios/aircraft); each solve's ranks over the hosts of an MPI --hostfile, its\n"
                        "       case in --work-dir (a folder every host sees; docs/cluster.md)\n");
        return 2;
    }
    if ((o->np > 0 || o->aircraft_given || o->hostfile || o->work_dir) && !o->openfoam) {
        fprintf(stderr, "disim airwaked: %s is the OpenFOAM engine's (--engine openfoam)\n",
                o->np > 0 ? "--np" : o->aircraft_given ? "--aircraft" : o->hostfile ? "--hostfile" : "--work-dir");
        return 2;
    }
    return 0;
}

int cmd_airwaked(int argc, char **argv)
{
    long ncores = sysconf(_SC_NPROCESSORS_ONLN);
    airwaked_args a = {NULL, "scenarios/ships", "scenarios/aircraft", NULL, NULL, ncores, 0, 0, 1, 0, 0, 0, 0};
    int prc = airwaked_parse(argc, argv, &a);
    if (prc != 0)
        return prc;
    const char *dir = a.dir, *ships = a.ships;
    long jobs = a.jobs, max_iter = a.max_iter;
    int once = a.once, use_lcm = a.use_lcm;
    if (a.openfoam && !a.jobs_given) /* each build runs np ranks */
        jobs = ncores / (a.np > 0 ? a.np : 2);
    if (jobs < 1)
        jobs = 1;
    app_log al = {"airwaked", 0};
    core_log log = {app_log_stderr, &al, CORE_LOG_INFO};
    core_err err = {0};
    foam_opts fo;
    foam_opts_default(&fo);
    fo.np = a.np > 0 ? (int)a.np : 2;
    fo.max_iter = (int)max_iter;
    fo.log = &log;
    fo.hostfile = a.hostfile;
    fo.work_dir = a.work_dir;
    char why[300];
    if (a.openfoam && !foam_available(&fo, why, sizeof why)) { /* before the database is touched */
        fprintf(stderr, "disim airwaked: the OpenFOAM engine cannot run: %s\n", why);
        return 1;
    }
    awdb *db = awdb_open(dir, &log, &err);
    if (db && awdb_engine_claim(db, a.openfoam ? "openfoam" : "embedded", &err) != 0) {
        fprintf(stderr, "disim airwaked: %s\n", err.msg);
        awdb_close(db);
        return 1;
    }
    awdb_embedded *emb = db && !a.openfoam
                             ? awdb_embedded_create(ships, (int)max_iter, (int)(ncores / jobs > 0 ? ncores / jobs : 1), &log, &err)
                             : NULL;
    foam_engine *fe = db && a.openfoam ? foam_engine_create(ships, a.aircraft, &fo, &err) : NULL;
    if (!db || (!emb && !fe)) {
        fprintf(stderr, "disim airwaked: %s\n", err.msg);
        awdb_embedded_destroy(emb);
        awdb_close(db);
        return 1;
    }
    if (emb)
        awdb_embedded_set_db(emb, db);
    if (fe)
        foam_engine_set_db(fe, db);
    daemon_ctx ctx;
    memset(&ctx, 0, sizeof ctx);
    ctx.db = db;
    ctx.tty = isatty(2);
    ctx.log = &log;
    pthread_mutex_init(&ctx.mu, NULL);
    lcm_subscription_t *sub = NULL;
    if (use_lcm) {
        ctx.lc = lcm_create(disim_lcm_url(NULL));
        if (!ctx.lc)
            fprintf(stderr, "disim airwaked: LCM unavailable: serving the folder queue only\n");
        else
            sub = lcm_subscribe(ctx.lc, DISIM_CH_AIRWAKE_REQUEST, on_request_raw, &ctx);
    }
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    awdb_engine eng;
    if (emb)
        awdb_embedded_engine(emb, &eng);
    else
        foam_engine_get(fe, &eng);
    awdb_builder_opts o = {(int)jobs, once, 0.2, on_status, &ctx, on_idle, &ctx, 0.0};
    fprintf(stderr, "airwaked: serving %s with %ld job%s (ships from %s)%s%s\n", dir, jobs, jobs > 1 ? "s" : "",
            ships, ctx.lc ? ", LCM requests on " DISIM_CH_AIRWAKE_REQUEST : "",
            fe ? ", engine openfoam" : "");
    int rc = awdb_builder_run(db, &eng, &o, &stop_flag, &err);
    if (rc)
        fprintf(stderr, "disim airwaked: %s\n", err.msg);
    if (ctx.lc) {
        lcm_unsubscribe(ctx.lc, sub);
        lcm_destroy(ctx.lc);
    }
    awdb_embedded_destroy(emb);
    foam_engine_destroy(fe);
    awdb_close(db);
    return rc ? 1 : 0;
}
