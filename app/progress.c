/* progress.c -- the status line while disim shol waits for an airwake
 * field (progress.h). Reads the database's state once a second (a folder
 * scan and one small file per running build) and rewrites one line on a
 * terminal; silent otherwise. */
#include "progress.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>

void app_progress_init(app_progress *p, awdb *db, int tty)
{
    memset(p, 0, sizeof *p);
    p->db = db;
    p->tty = tty;
    p->period_s = 1.0;
    p->last_s = -1.0;
}

/* A name without its 16-digit hash: "CG-47_shiponly_v15.00_d-030.00_off_coarse". */
static void short_name(const char *name, char *out, size_t n)
{
    size_t l = strlen(name);
    if (l > 17 && name[l - 17] == '_')
        l -= 17;
    snprintf(out, n, "%.*s", (int)(l < n ? l : n - 1), name);
}

static void duration(double s, char *out, size_t n)
{
    if (s < 120.0)
        snprintf(out, n, "%.0f s", s);
    else if (s < 7200.0)
        snprintf(out, n, "%.0f min", s / 60.0);
    else
        snprintf(out, n, "%.1f h", s / 3600.0);
}

/* "it 120/900 13 %, res 1.2e-03, <= 4 min left": the time left is to the
 * cap, an upper bound (a field can stop earlier, at convergence). Short,
 * so that the whole line fits 80 columns. */
static void run_text(const awdb_run_progress *r, char *out, size_t n)
{
    if (!r->have || r->iteration == 0) {
        snprintf(out, n, "build starting"); /* claimed; the solver sets up its grid */
        return;
    }
    char left[48] = "";
    if (r->left_s >= 0.0) {
        char d[24];
        duration(r->left_s, d, sizeof d);
        snprintf(left, sizeof left, ", <= %s left", d);
    }
    if (r->max_iterations > 0)
        snprintf(out, n, "it %d/%d %.0f %%, res %.1e%s", r->iteration, r->max_iterations, 100.0 * r->frac,
                 r->residual, left);
    else
        snprintf(out, n, "it %d, res %.1e", r->iteration, r->residual);
}

/* Most telling first, the name last (a narrow terminal cuts the end, and
 * the name is in the "waiting for airwake" line above):
 * "waited 1 min | it 120/900 13 %, res 1.2e-03, <= 4 min left | 3 ready, 5 queued | NAME". */
void app_progress_format(const awdb_progress *p, const char *name, double waited_s, char *buf, size_t n)
{
    char sn[AWDB_NAME_MAX], what[AWDB_NAME_MAX + 160], waited[24], rt[128];
    short_name(name, sn, sizeof sn);
    const awdb_run_progress *mine = awdb_progress_find(p, name);
    if (mine) {
        run_text(mine, rt, sizeof rt);
        snprintf(what, sizeof what, "%s", rt);
    } else if (p->n_runs > 0) {
        /* queued behind another build: how that one goes */
        run_text(&p->runs[0], rt, sizeof rt);
        snprintf(what, sizeof what, "queued; building another: %s", rt);
    } else {
        snprintf(what, sizeof what, "queued; %s", p->builder_alive ? "builder between fields" : "builder starting");
    }
    duration(waited_s, waited, sizeof waited);
    snprintf(buf, n, "waited %s | %s | %d ready, %d queued | %s", waited, what, p->ready, p->queued, sn);
}

void app_progress_wait(void *user, const awdb_key *key, double waited_s)
{
    app_progress *pw = user;
    if (!pw->tty)
        return; /* quiet in logs */
    char name[AWDB_NAME_MAX];
    awdb_key_name(key, name, sizeof name);
    /* a new wait (another key, or the clock restarted) shows at once */
    int fresh = strcmp(name, pw->name) != 0 || waited_s < pw->last_s;
    if (!fresh && pw->last_s >= 0.0 && waited_s - pw->last_s < pw->period_s)
        return;
    awdb_progress st;
    core_err err = {0};
    if (awdb_progress_read(pw->db, &st, &err) != 0)
        return; /* the wait's own checks report a database that went away */
    pw->last_s = waited_s;
    snprintf(pw->name, sizeof pw->name, "%s", name);
    char line[1024];
    app_progress_format(&st, name, waited_s, line, sizeof line);
    int cols = pw->columns;
    if (cols <= 0) {
        /* $COLUMNS first (as ls(1) takes it), then the terminal's size */
        const char *env = getenv("COLUMNS");
        char *end = NULL;
        long c = env ? strtol(env, &end, 10) : 0;
        struct winsize ws;
        if (env && end != env && !*end && c > 1 && c < 10000)
            cols = (int)c;
        else
            cols = ioctl(STDERR_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0 ? ws.ws_col : 80;
    }
    /* one character short of the width: a line that wraps cannot be
     * rewritten with \r */
    if (cols > 1 && (size_t)(cols - 1) < sizeof line)
        line[cols - 1] = '\0';
    fprintf(stderr, "\r\033[K%s", line);
    fflush(stderr);
}
