/* builder.c -- the background airwake builder: claims queued requests (a
 * hard link into running/ is the claim, so two claimers cannot both win),
 * runs up to `jobs` CFD builds at once in threads, publishes each build's
 * progress (running/NAME.prog, replaced by rename), commits each field
 * atomically (checksum file prepared, field renamed, checksum renamed), and
 * recovers from a crash by returning running/ requests to the front of the
 * queue and removing stray temporaries and progress files. */
#include "awdb_private.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

typedef struct job {
    struct builder *b;
    pthread_t thread;
    int active, done;
    awdb_key key;
    char name[200];
} job;

typedef struct builder {
    awdb *db;
    const awdb_engine *engine;
    const awdb_builder_opts *opts;
    volatile sig_atomic_t *stop;
    pthread_mutex_t status_lock; /* one status callback at a time */
    job *jobs;
} builder;

static void status(builder *b, const awdb_key *k, awdb_state s, double frac, double res, int it,
                   const char *path, const char *msg)
{
    if (!b->opts->status)
        return;
    pthread_mutex_lock(&b->status_lock);
    b->opts->status(b->opts->status_user, k, s, frac, res, it, path, msg);
    pthread_mutex_unlock(&b->status_lock);
}

typedef struct prog {
    job *j;
    struct timespec last;
    /* the progress file: the build's start, the first report (iteration
     * and time, for the rate), the last write, the cap once known */
    struct timespec t0, first, written;
    int have_first, written_once, iter0, max_iter;
} prog;

static double secs(struct timespec a, struct timespec b)
{
    return (double)(b.tv_sec - a.tv_sec) + 1e-9 * (double)(b.tv_nsec - a.tv_nsec);
}

/* running/NAME.prog, replaced by rename so that a reader finds a whole file
 * or none. Advisory: not synced (a restarted builder removes them all), and
 * a write that fails is skipped (the next one may succeed). */
static void write_progress(awdb *db, const char *name, int iter, int max_iter, double residual, double frac,
                           double elapsed_s, double left_s)
{
    char path[AWDB_PATH], tmp[AWDB_PATH + 32], text[512];
    awdb_path(db, path, sizeof path, "running", name, ".prog");
    if (awdb_fmt(tmp, sizeof tmp, "%s.tmp%ld", path, (long)getpid()) < 0)
        return;
    int len = awdb_fmt(text, sizeof text,
                       "[progress]\niteration = %d\nmax_iterations = %d\nresidual = %.6e\nfraction = %.6f\n"
                       "elapsed_s = %.3f\nleft_s = %.3f\n",
                       iter, max_iter, residual, frac, elapsed_s, left_s);
    FILE *f = len > 0 ? fopen(tmp, "w") : NULL;
    if (!f)
        return;
    int ok = fwrite(text, 1, (size_t)len, f) == (size_t)len;
    ok = fclose(f) == 0 && ok;
    if (!ok || rename(tmp, path) != 0)
        remove(tmp);
}

static void remove_progress(awdb *db, const char *name)
{
    char path[AWDB_PATH];
    awdb_path(db, path, sizeof path, "running", name, ".prog");
    remove(path);
}

static int on_progress(void *user, double frac, double residual, int iter)
{
    prog *p = user;
    builder *b = p->j->b;
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    /* Status at most twice a second: enough for a display, light on LCM. */
    if ((now.tv_sec - p->last.tv_sec) * 1e9 + (now.tv_nsec - p->last.tv_nsec) > 5e8) {
        p->last = now;
        status(b, &p->j->key, AWDB_RUNNING, frac, residual, iter, "", "");
    }
    /* The cap: the engines report frac = iteration / cap. */
    if (frac > 0.0 && iter > 0)
        p->max_iter = (int)lround(iter / frac);
    if (!p->have_first) {
        p->have_first = 1;
        p->first = now;
        p->iter0 = iter;
    }
    double interval = b->opts->progress_interval_s > 0.0 ? b->opts->progress_interval_s : 1.0;
    if (!p->written_once || secs(p->written, now) >= interval) {
        p->written_once = 1;
        p->written = now;
        /* the time left at the rate since the first report, up to the cap */
        double dt = secs(p->first, now), left = -1.0;
        if (p->max_iter > 0 && iter > p->iter0 && dt > 0.0)
            left = fmax(0.0, (p->max_iter - iter) * dt / (iter - p->iter0));
        write_progress(b->db, p->j->name, iter, p->max_iter, residual, frac, secs(p->t0, now), left);
    }
    return *b->stop != 0;
}

/* failed/NAME.txt: the reason a key failed, read by awdb_query. 0, or < 0
 * with err (may be NULL). */
static int write_failure(awdb *db, const char *name, const char *reason, core_err *err)
{
    char failed[AWDB_PATH], text[1200];
    awdb_path(db, failed, sizeof failed, "failed", name, ".txt");
    awdb_fmt(text, sizeof text, "%s\n", reason);
    return awdb_write_atomic(failed, text, err);
}

static int commit(awdb *db, const awdb_key *k, const char *name, const char *tmp, core_err *err)
{
    /* The engine's file on disk before its name and checksum are: after a
     * power cut a durable .sum must not describe a field still in the page
     * cache (the checksum would catch it, at the cost of a rebuild). */
    if (core_sync_path(tmp) != 0)
        return core_err_set(err, -1, "%s: cannot sync: %s", tmp, strerror(errno));
    uint64_t crc, size;
    int rc = awdb_file_crc64(tmp, &crc, &size, err);
    if (rc)
        return rc;
    char text[AWDB_KEY_TEXT + 200], key[AWDB_KEY_TEXT], sum[AWDB_PATH], sumtmp[AWDB_PATH + 8], h5[AWDB_PATH];
    awdb_key_format(k, key, sizeof key);
    awdb_fmt(text, sizeof text, "[field]\nsize = %llu\ncrc64 = %016llx\n\n%s", (unsigned long long)size,
             (unsigned long long)crc, key);
    awdb_path(db, sum, sizeof sum, "fields", name, ".sum");
    awdb_path(db, h5, sizeof h5, "fields", name, ".h5");
    awdb_fmt(sumtmp, sizeof sumtmp, "%s.part", sum);
    /* The .sum is written under a temporary name first; the entry becomes
     * valid only with the final rename, after the field is in place. */
    if ((rc = awdb_write_atomic(sumtmp, text, err)))
        return rc;
    if (rename(tmp, h5) != 0 || rename(sumtmp, sum) != 0) {
        int e = errno;
        remove(sumtmp);
        return core_err_set(err, -1, "%s: cannot commit: %s", h5, strerror(e));
    }
    /* the two renames themselves (the entry is valid already; a failure
     * here only weakens durability) */
    char dir[AWDB_PATH];
    awdb_fmt(dir, sizeof dir, "%s/fields", db->dir);
    if (core_sync_path(dir) != 0)
        core_log_msg(db->log, CORE_LOG_WARN, "%s: cannot sync: %s", dir, strerror(errno));
    return 0;
}

static void *run_job(void *arg)
{
    job *j = arg;
    builder *b = j->b;
    awdb *db = b->db;
    char running[AWDB_PATH], tmp[AWDB_PATH + 64], warm[AWDB_PATH], path[AWDB_PATH];
    awdb_path(db, running, sizeof running, "running", j->name, ".req");
    awdb_fmt(tmp, sizeof tmp, "%s/fields/.tmp-%s.h5", db->dir, j->name);
    core_err err = {0};
    if (awdb_query(db, &j->key, path, sizeof path) == AWDB_READY) {
        /* Built by someone else since it was queued (or before a crash). */
        remove(running);
        status(b, &j->key, AWDB_READY, 1.0, 0.0, 0, path, "");
        j->done = 1;
        return NULL;
    }
    const char *warm_path = awdb_nearest(db, &j->key, warm, sizeof warm) == 0 ? warm : NULL;
    core_log_msg(db->log, CORE_LOG_INFO, "building %s%s%s", j->name, warm_path ? " from " : "",
                 warm_path ? warm_path : "");
    status(b, &j->key, AWDB_RUNNING, 0.0, 0.0, 0, "", "");
    prog p;
    memset(&p, 0, sizeof p);
    p.j = j;
    clock_gettime(CLOCK_MONOTONIC, &p.t0);
    /* a reader sees the build started before its first iteration */
    write_progress(db, j->name, 0, 0, 0.0, 0.0, 0.0, -1.0);
    remove(tmp);
    int rc = b->engine->build(b->engine->user, &j->key, warm_path, tmp, on_progress, &p, &err);
    remove_progress(db, j->name); /* before the claim goes: no progress without its request */
    int committed = 0;
    if (rc == 0 && !*b->stop) {
        rc = commit(db, &j->key, j->name, tmp, &err);
        committed = rc == 0;
    }
    remove(tmp);
    if (!committed && *b->stop) {
        /* Stopped, not failed (whatever the engine returned): back to the
         * front of the queue. */
        char q[AWDB_PATH + 300], file[300];
        awdb_fmt(file, sizeof file, "0000000000000000000000-%s", j->name);
        awdb_path(db, q, sizeof q, "queue", file, ".req");
        rename(running, q);
        status(b, &j->key, AWDB_QUEUED, 0.0, 0.0, 0, "", "builder stopped");
    } else if (rc != 0) {
        core_err werr = {0};
        /* if it cannot be written, the reason lives in the log only */
        if (write_failure(db, j->name, err.msg[0] ? err.msg : "engine failed", &werr) != 0)
            core_log_msg(db->log, CORE_LOG_ERROR, "%s", werr.msg);
        remove(running);
        core_log_msg(db->log, CORE_LOG_ERROR, "%s failed: %s", j->name, err.msg);
        status(b, &j->key, AWDB_FAILED, 0.0, 0.0, 0, "", err.msg);
    } else {
        remove(running);
        awdb_path(db, path, sizeof path, "fields", j->name, ".h5");
        core_log_msg(db->log, CORE_LOG_INFO, "ready %s", path);
        status(b, &j->key, AWDB_READY, 1.0, 0.0, 0, path, "");
    }
    j->done = 1;
    return NULL;
}

/* 1 if name is a temporary of the database that nobody is writing now:
 * ".tmp-NAME.h5" and the engine's side files (the builder's field being
 * built), "NAME.sum.part" (a checksum prepared), "FILE.tmpPID"
 * (awdb_write_atomic) of a process that has exited. Exact patterns, not
 * substrings: ship and aircraft names may contain ".tmp" or ".part"
 * ("LHA.partial"), and such entries are not temporaries. The PID test
 * matters in queue/, where clients write while the builder starts. */
static int stray_temporary(const char *name)
{
    size_t l = strlen(name);
    if (!strncmp(name, ".tmp-", 5) || (l > 5 && !strcmp(name + l - 5, ".part")))
        return 1;
    size_t d = l;
    while (d > 0 && name[d - 1] >= '0' && name[d - 1] <= '9')
        d--;
    if (d == l || d < 4 || strncmp(name + d - 4, ".tmp", 4))
        return 0;
    long pid = strtol(name + d, NULL, 10);
    return pid <= 0 || (kill((pid_t)pid, 0) != 0 && errno == ESRCH);
}

/* 1 if name is a progress file or a progress file's temporary
 * ("NAME.prog", "NAME.prog.tmpPID"). */
static int progress_file(const char *name)
{
    size_t l = strlen(name);
    if (l > 5 && !strcmp(name + l - 5, ".prog"))
        return 1;
    const char *t = strstr(name, ".prog.tmp");
    if (!t)
        return 0;
    for (t += 9; *t; t++)
        if (*t < '0' || *t > '9')
            return 0;
    return 1;
}

/* After a crash: running/ back to the front of the queue, progress files
 * and temporaries out. Every progress file is stale here: the builder that
 * wrote it held the lock this one now holds, so it has exited. */
static void recover(awdb *db)
{
    char p[AWDB_PATH];
    awdb_fmt(p, sizeof p, "%s/running", db->dir);
    DIR *d = opendir(p);
    struct dirent *e;
    while (d && (e = readdir(d))) {
        size_t l = strlen(e->d_name);
        if (progress_file(e->d_name)) {
            char f[AWDB_PATH + 300];
            awdb_fmt(f, sizeof f, "%s/%s", p, e->d_name);
            remove(f);
            continue;
        }
        if (l < 5 || strcmp(e->d_name + l - 4, ".req"))
            continue;
        char from[AWDB_PATH + 300], to[AWDB_PATH + 300];
        awdb_fmt(from, sizeof from, "%s/%s", p, e->d_name);
        awdb_fmt(to, sizeof to, "%s/queue/0000000000000000000000-%s", db->dir, e->d_name);
        if (rename(from, to) == 0)
            core_log_msg(db->log, CORE_LOG_INFO, "requeued %s (interrupted build)", e->d_name);
    }
    if (d)
        closedir(d);
    static const char *subs[] = {"fields", "queue", "failed"};
    for (int i = 0; i < 3; i++) {
        awdb_fmt(p, sizeof p, "%s/%s", db->dir, subs[i]);
        d = opendir(p);
        while (d && (e = readdir(d))) {
            if (!stray_temporary(e->d_name))
                continue;
            char f[AWDB_PATH + 300];
            awdb_fmt(f, sizeof f, "%s/%s", p, e->d_name);
            remove(f);
            core_log_msg(db->log, CORE_LOG_INFO, "removed temporary %s", f);
        }
        if (d)
            closedir(d);
    }
}

static int cmp_str(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

/* One queued request as the claim orders it. */
typedef struct qent {
    char *file;               /* SEQ-NAME.req */
    char stem[AWDB_NAME_MAX]; /* NAME */
    char src[AWDB_NAME_MAX];  /* the engine's source (engine.source), "" none */
    int src_ready;            /* that source is in the database */
    int cls;                  /* 0 made at once, 1 waited for, 2 the rest (awdb_builder_run) */
    int ncoarser;             /* a whole-domain ship-only key: its own wind's coarser levels */
    char coarser[3][AWDB_NAME_MAX];
} qent;

static int cmp_qent(const void *pa, const void *pb)
{
    const qent *a = pa, *b = pb;
    if (a->cls != b->cls)
        return a->cls < b->cls ? -1 : 1;
    return strcmp(a->file, b->file);
}

/* The names some running process waits for (waiting/NAME.PID), sorted;
 * the marks of processes that have ended are removed. */
static char **waited_names(awdb *db, size_t *n_out)
{
    char dir[AWDB_PATH];
    awdb_fmt(dir, sizeof dir, "%s/waiting", db->dir);
    *n_out = 0;
    DIR *d = opendir(dir);
    if (!d)
        return NULL;
    char **v = NULL;
    size_t n = 0, cap = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        const char *dot = strrchr(e->d_name, '.');
        if (e->d_name[0] == '.' || !dot || !dot[1] || strspn(dot + 1, "0123456789") != strlen(dot + 1))
            continue;
        long pid = strtol(dot + 1, NULL, 10);
        if (pid <= 0 || (kill((pid_t)pid, 0) != 0 && errno == ESRCH)) {
            char f[AWDB_PATH + 300];
            if (awdb_fmt(f, sizeof f, "%s/%s", dir, e->d_name) >= 0)
                remove(f);
            continue;
        }
        if (n == cap) {
            cap = cap ? 2 * cap : 16;
            char **g = realloc(v, cap * sizeof *g);
            if (!g)
                break;
            v = g;
        }
        if (!(v[n] = strndup(e->d_name, (size_t)(dot - e->d_name))))
            break;
        n++;
    }
    closedir(d);
    if (n > 1)
        qsort(v, n, sizeof *v, cmp_str);
    *n_out = n;
    return v;
}

static int is_waited(char **w, size_t nw, const char *name)
{
    return nw > 0 && bsearch(&name, w, nw, sizeof *w, cmp_str) != NULL;
}

/* The queue (names, n of them, taken over) in the order it is built
 * (awdb_builder_run); entries without a name (a failed strdup) are left
 * out, their file NULL at the end. The caller frees each file and the
 * array; NULL when out of memory (names then still the caller's). */
static qent *queue_order(builder *b, const char *qdir, char **names, size_t n)
{
    qent *q = calloc(n ? n : 1, sizeof *q);
    if (!q)
        return NULL;
    size_t nw = 0;
    char **w = waited_names(b->db, &nw);
    for (size_t i = 0; i < n; i++) {
        qent *e = &q[i];
        e->file = names[i];
        names[i] = NULL;
        e->cls = 2;
        if (!e->file)
            continue;
        const char *stem = strchr(e->file, '-') + 1;
        awdb_fmt(e->stem, sizeof e->stem, "%.*s", (int)(strlen(stem) - 4), stem);
        char path[AWDB_PATH + 300];
        awdb_fmt(path, sizeof path, "%s/%s", qdir, e->file);
        core_err err = {0};
        core_ini *ini = core_ini_load(path, &err);
        awdb_key key, src;
        int ok = ini && awdb_key_read(ini, &key, &err) == 0;
        core_ini_destroy(ini);
        /* a request that cannot be read is not held (the claim reports it) */
        if (!ok)
            continue;
        /* a whole-domain ship-only field starts from its own wind's
         * coarser field (awdb_nearest): it waits for one building */
        if (key.rotor == CORE_ROTOR_OFF && !(key.zone_ref_mps > 0.0)) {
            static const core_grid_level by_rank[] = {CORE_GRID_QUICK, CORE_GRID_COARSE, CORE_GRID_DEFAULT};
            for (int r = 0; r < core_grid_rank(key.grid) && r < 3; r++) {
                awdb_key c = key;
                c.grid = by_rank[r];
                if (awdb_key_canon(&c, &err) == 0)
                    awdb_key_name(&c, e->coarser[e->ncoarser++], AWDB_NAME_MAX);
            }
        }
        if (!b->engine->source || !b->engine->source(b->engine->user, &key, &src))
            continue;
        awdb_key_name(&src, e->src, sizeof e->src);
        e->src_ready = awdb_query(b->db, &src, NULL, 0) == AWDB_READY;
    }
    for (size_t i = 0; i < n; i++) {
        if (!q[i].file)
            continue;
        if (q[i].src[0] && q[i].src_ready)
            q[i].cls = 0;
        else if (is_waited(w, nw, q[i].stem))
            q[i].cls = 1;
    }
    /* the source of a mirror someone waits for is waited for too */
    for (size_t i = 0; i < n; i++)
        if (q[i].file && q[i].cls == 1 && q[i].src[0])
            for (size_t k = 0; k < n; k++)
                if (q[k].file && q[k].cls == 2 && !strcmp(q[k].stem, q[i].src))
                    q[k].cls = 1;
    for (size_t i = 0; i < nw; i++)
        free(w[i]);
    free(w);
    /* submission order (the names') within a class */
    size_t m = 0;
    for (size_t i = 0; i < n; i++)
        if (q[i].file)
            q[m++] = q[i];
    if (m > 1)
        qsort(q, m, sizeof *q, cmp_qent);
    for (size_t i = m; i < n; i++)
        q[i].file = NULL;
    return q;
}

/* 1 if the request for name runs, or is queued before q[i]. */
static int ahead(builder *b, const qent *q, size_t i, const char *name)
{
    char run[AWDB_PATH + 300];
    awdb_path(b->db, run, sizeof run, "running", name, ".req");
    if (access(run, F_OK) == 0)
        return 1;
    for (size_t k = 0; k < i; k++)
        if (q[k].file && !strcmp(q[k].stem, name))
            return 1;
    return 0;
}

/* Whether q[i] waits for the field the engine makes it from (while that
 * source runs or is queued ahead of it, building both would solve twice),
 * or for its own wind's coarser field to start from (a flight's quick,
 * coarse and default fields: each finer solve then starts from the
 * coarser one's solution). */
static int held_back(builder *b, const qent *q, size_t i)
{
    if (q[i].src[0] && q[i].src_ready)
        return 0; /* made at once from its source: nothing to start from */
    if (q[i].src[0] && ahead(b, q, i, q[i].src))
        return 1;
    for (int c = 0; c < q[i].ncoarser; c++)
        if (ahead(b, q, i, q[i].coarser[c]))
            return 1;
    return 0;
}

/* Claim the first queued request in the builder's order (awdb_builder_run)
 * that is not held back: 1 with *j filled, 0 if there is none. */
static int claim(builder *b, job *j)
{
    awdb *db = b->db;
    char qdir[AWDB_PATH];
    awdb_fmt(qdir, sizeof qdir, "%s/queue", db->dir);
    DIR *d = opendir(qdir);
    if (!d)
        return 0;
    char **names = NULL;
    size_t n = 0, cap = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        size_t l = strlen(e->d_name);
        if (l < 5 || strcmp(e->d_name + l - 4, ".req") || e->d_name[0] == '.' || !strchr(e->d_name, '-'))
            continue;
        if (n == cap) {
            cap = cap ? 2 * cap : 32;
            char **nn = realloc(names, cap * sizeof *nn);
            if (!nn)
                break;
            names = nn;
        }
        names[n++] = strdup(e->d_name);
    }
    closedir(d);
    qent *order = queue_order(b, qdir, names, n);
    if (!order) {
        for (size_t i = 0; i < n; i++)
            free(names[i]);
        free(names);
        return 0;
    }
    int got = 0;
    for (size_t i = 0; i < n && !got; i++) {
        if (!order[i].file)
            continue;
        const char *qname = order[i].file;
        char q[AWDB_PATH + 300], run[AWDB_PATH + 300];
        awdb_fmt(q, sizeof q, "%s/%s", qdir, qname);
        if (held_back(b, order, i))
            continue;
        const char *stem = strchr(qname, '-') + 1;
        awdb_fmt(j->name, sizeof j->name, "%.*s", (int)(strlen(stem) - 4), stem);
        awdb_path(db, run, sizeof run, "running", j->name, ".req");
        core_ini *ini = NULL;
        core_err err = {0};
        if (link(q, run) != 0) {
            /* Already running: this is a duplicate request. Gone (ENOENT):
             * another builder or a clean-up took it. Anything else (a file
             * system without hard links, EPERM) would leave the request
             * skipped on every scan, silently and for ever (and an
             * --exit-when-idle builder never idle): it fails, saying why. */
            int e = errno;
            /* errors that every later scan would meet again; others (a full
             * disk, EIO) may pass, and the request waits for the next scan */
            int lasting = e == EPERM || e == EMLINK || e == EOPNOTSUPP || e == EXDEV || e == EROFS || e == EACCES ||
                          e == ENOTDIR;
            if (e == EEXIST) {
                remove(q);
            } else if (lasting) {
                char text[1200];
                awdb_fmt(text, sizeof text, "cannot claim the request: link %s -> %s: %s", q, run, strerror(e));
                core_err werr = {0};
                if (write_failure(db, j->name, text, &werr) == 0) /* the reason kept, or the request stays */
                    remove(q);
                core_log_msg(db->log, CORE_LOG_ERROR, "%s: cannot claim it (link to running/: %s)%s%s", qname,
                             strerror(e), werr.msg[0] ? "; " : "", werr.msg);
            } else if (e != ENOENT) {
                core_log_msg(db->log, CORE_LOG_WARN, "%s: cannot claim it now (link to running/: %s); retried",
                             qname, strerror(e));
            }
            continue;
        }
        remove(q);
        ini = core_ini_load(run, &err);
        int rc = ini ? awdb_key_read(ini, &j->key, &err) : -1;
        if (!rc)
            rc = core_ini_check_unused(ini, &err);
        core_ini_destroy(ini);
        if (!rc) {
            /* The ranges and rules awdb_submit applies (a thrust with the
             * rotor on, a positive mean load...): a request written by
             * another program is held to them too, and built as the
             * canonical key its name stands for. */
            core_err cerr = {0};
            if (awdb_key_canon(&j->key, &cerr) != 0)
                rc = core_err_set(&err, -1, "%s: %s", run, cerr.msg);
        }
        char check[200];
        if (!rc) {
            awdb_key_name(&j->key, check, sizeof check);
            if (strcmp(check, j->name))
                rc = core_err_set(&err, -1, "%s: the key does not match the file name", run);
        }
        if (rc) {
            char text[1200];
            awdb_fmt(text, sizeof text, "corrupt request: %s", err.msg);
            write_failure(db, j->name, text, NULL);
            remove(run);
            core_log_msg(db->log, CORE_LOG_ERROR, "corrupt request %s: %s", qname, err.msg);
            continue;
        }
        got = 1;
    }
    for (size_t i = 0; i < n; i++)
        free(order[i].file);
    free(order);
    free(names);
    return got;
}

int awdb_builder_run(awdb *db, const awdb_engine *engine, const awdb_builder_opts *opts,
                     volatile sig_atomic_t *stop, core_err *err)
{
    if (opts->jobs < 1 || opts->jobs > 256)
        return core_err_set(err, -1, "builder: jobs = %d: expected 1 to 256", opts->jobs);
    char lockp[AWDB_PATH];
    awdb_fmt(lockp, sizeof lockp, "%s/builder.lock", db->dir);
    /* close-on-exec: a process an engine starts must not keep the lock
     * after the builder is gone */
    int fd = open(lockp, O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0)
        return core_err_set(err, -1, "%s: cannot open: %s", lockp, strerror(errno));
    /* A client's awdb_builder_alive holds the lock (shared) for an instant:
     * wait such a probe out (up to 1 s) rather than refuse as if a builder
     * served the database. */
    int lock_errno = 0;
    for (int t = 0;; t++) {
        lock_errno = flock(fd, LOCK_EX | LOCK_NB) == 0 ? 0 : errno;
        if (lock_errno != EWOULDBLOCK || t == 20)
            break;
        struct timespec ts = {0, 50000000};
        nanosleep(&ts, NULL);
    }
    if (lock_errno != 0 && lock_errno != EWOULDBLOCK) {
        close(fd);
        return core_err_set(err, -1, "%s: cannot lock: %s", lockp, strerror(lock_errno));
    }
    if (lock_errno != 0) {
        char pid[32] = "";
        ssize_t r = read(fd, pid, sizeof pid - 1);
        pid[r > 0 ? r : 0] = '\0';
        close(fd);
        return core_err_set(err, -1, "%s: another builder (pid %s) already serves this database",
                            db->dir, pid[0] ? strtok(pid, "\n") : "?");
    }
    char pid[32];
    int pl = awdb_fmt(pid, sizeof pid, "%ld\n", (long)getpid());
    if (ftruncate(fd, 0) != 0 || write(fd, pid, pl) != pl)
        core_log_msg(db->log, CORE_LOG_WARN, "%s: cannot record the pid", lockp);
    recover(db);

    builder b = {db, engine, opts, stop, PTHREAD_MUTEX_INITIALIZER, NULL};
    b.jobs = calloc(opts->jobs, sizeof *b.jobs);
    if (!b.jobs) {
        close(fd);
        return core_err_set(err, -1, "builder: out of memory");
    }
    int rc = 0;
    for (;;) {
        int active = 0;
        for (int i = 0; i < opts->jobs; i++) {
            job *j = &b.jobs[i];
            if (j->active && j->done) {
                pthread_join(j->thread, NULL);
                j->active = 0;
            }
            if (!j->active && !*stop) {
                memset(j, 0, sizeof *j);
                j->b = &b;
                if (claim(&b, j)) {
                    status(&b, &j->key, AWDB_QUEUED, 0, 0, 0, "", "");
                    if (pthread_create(&j->thread, NULL, run_job, j) != 0) {
                        rc = core_err_set(err, -1, "builder: cannot start a thread");
                        *stop = 1;
                    } else
                        j->active = 1;
                }
            }
            active += j->active;
        }
        if (active == 0 && (*stop || opts->exit_when_idle)) {
            int q, r;
            awdb_pending(db, &q, &r);
            if (*stop || q == 0)
                break;
        }
        if (opts->idle)
            opts->idle(opts->idle_user);
        struct timespec ts = {(time_t)opts->poll_s, (long)((opts->poll_s - (time_t)opts->poll_s) * 1e9)};
        if (ts.tv_sec == 0 && ts.tv_nsec < 1000000)
            ts.tv_nsec = 1000000;
        nanosleep(&ts, NULL);
    }
    free(b.jobs);
    pthread_mutex_destroy(&b.status_lock);
    flock(fd, LOCK_UN);
    close(fd);
    return rc;
}
