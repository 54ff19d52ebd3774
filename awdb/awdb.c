/* awdb.c -- the airwake database: the folder layout, atomic writes, checked
 * reads, requests. The layout and its crash-safety argument are in awdb.h. */
#include "awdb_private.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <unistd.h>

int awdb_fmt(char *out, size_t n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int w = vsnprintf(out, n, fmt, ap);
    va_end(ap);
    return (w < 0 || (size_t)w >= n) ? -1 : w;
}

const char *awdb_state_name(awdb_state s)
{
    static const char *n[] = {"absent", "queued", "running", "ready", "failed"};
    return (unsigned)s < 5 ? n[s] : "?";
}

void awdb_path(const awdb *db, char *out, size_t n, const char *sub, const char *name, const char *ext)
{
    awdb_fmt(out, n, "%s/%s/%s%s", db->dir, sub, name, ext);
}

int awdb_write_atomic(const char *path, const char *text, core_err *err)
{
    char tmp[AWDB_PATH + 32];
    awdb_fmt(tmp, sizeof tmp, "%s.tmp%ld", path, (long)getpid());
    FILE *f = fopen(tmp, "w");
    if (!f)
        return core_err_set(err, -1, "%s: cannot create: %s", tmp, strerror(errno));
    size_t len = strlen(text);
    int ok = fwrite(text, 1, len, f) == len && fflush(f) == 0 && fsync(fileno(f)) == 0;
    ok = (fclose(f) == 0) && ok;
    if (!ok || rename(tmp, path) != 0) {
        int e = errno;
        remove(tmp);
        return core_err_set(err, -1, "%s: cannot write: %s", path, strerror(e));
    }
    /* the rename itself is durable only once its folder is synced (a
     * queue entry or a failure record that vanished after a power cut
     * would be a request lost) */
    char dir[AWDB_PATH + 32];
    awdb_fmt(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (slash == dir)
        slash[1] = '\0';
    else if (slash)
        *slash = '\0';
    else
        awdb_fmt(dir, sizeof dir, ".");
    if (core_sync_path(dir) != 0)
        return core_err_set(err, -1, "%s: written, but its folder %s cannot be synced: %s", path, dir,
                            strerror(errno));
    return 0;
}

void awdb_key_format(const awdb_key *k, char *buf, size_t n)
{
    int len = snprintf(buf, n,
             "[key]\nship = %s\naircraft = %s\nwod_speed_mps = %.17g\nwod_dir_rad = %.17g\n"
             "rotor = %d\nthrust_N = %.17g\nstation_S_m = %.17g, %.17g, %.17g\nradius_m = %.17g\n"
             "shaft_pitch_rad = %.17g\nshaft_roll_rad = %.17g\ngrid = %d\n",
             k->ship, k->aircraft[0] ? k->aircraft : "-", k->wod_speed_mps, k->wod_dir_rad, k->rotor,
             k->thrust_N, k->station_S_m[0], k->station_S_m[1], k->station_S_m[2], k->radius_m,
             k->shaft_pitch_rad, k->shaft_roll_rad, k->grid);
    if (k->zone_ref_mps > 0.0 && len >= 0 && (size_t)len < n)
        len += snprintf(buf + len, n - len, "zone_ref_mps = %.17g\n", k->zone_ref_mps);
    if (k->rotor != CORE_ROTOR_LOADED || len < 0 || (size_t)len >= n)
        return;
    /* The loaded disk. */
    len += snprintf(buf + len, n - len, "torque_Nm = %.17g\nroot_cut = %.17g\nccw_from_above = %d\nswirl =",
                    k->torque_Nm, k->root_cut, k->ccw_from_above);
    for (int i = 0; i < AWDB_LOAD_NR && (size_t)len < n; i++)
        len += snprintf(buf + len, n - len, "%s %.3f", i ? "," : "", k->swirl[i]);
    /* one line per azimuth: the INI reader's lines are short */
    for (int j = 0; j < AWDB_LOAD_NPSI && (size_t)len < n; j++) {
        len += snprintf(buf + len, n - len, "\nload_psi%02d =", j);
        for (int i = 0; i < AWDB_LOAD_NR && (size_t)len < n; i++)
            len += snprintf(buf + len, n - len, "%s %.3f", i ? "," : "", k->load[j * AWDB_LOAD_NR + i]);
    }
    if ((size_t)len < n)
        snprintf(buf + len, n - len, "\n");
}

int awdb_key_read(core_ini *ini, awdb_key *k, core_err *err)
{
    memset(k, 0, sizeof *k);
    long rotor = 0, grid = 0;
    int n = 0, rc;
    if ((rc = core_ini_get_string(ini, "key", "ship", 1, k->ship, sizeof k->ship, err)) ||
        (rc = core_ini_get_string(ini, "key", "aircraft", 1, k->aircraft, sizeof k->aircraft, err)) ||
        (rc = core_ini_get_double(ini, "key", "wod_speed_mps", 1, 0, 100, &k->wod_speed_mps, err)) ||
        (rc = core_ini_get_double(ini, "key", "wod_dir_rad", 1, -7, 7, &k->wod_dir_rad, err)) ||
        (rc = core_ini_get_int(ini, "key", "rotor", 1, 0, 2, &rotor, err)) ||
        (rc = core_ini_get_double(ini, "key", "thrust_N", 1, 0, 1e7, &k->thrust_N, err)) ||
        (rc = core_ini_get_doubles(ini, "key", "station_S_m", 1, -1000, 1000, k->station_S_m, 3, &n, err)) ||
        (rc = core_ini_get_double(ini, "key", "radius_m", 1, 0, 50, &k->radius_m, err)) ||
        (rc = core_ini_get_double(ini, "key", "shaft_pitch_rad", 1, -1, 1, &k->shaft_pitch_rad, err)) ||
        (rc = core_ini_get_double(ini, "key", "shaft_roll_rad", 1, -1, 1, &k->shaft_roll_rad, err)) ||
        (rc = core_ini_get_int(ini, "key", "grid", 1, 0, CORE_GRID_QUICK, &grid, err)))
        return rc < 0 ? rc : -1;
    /* optional: absent in whole-domain keys (1) */
    if ((rc = core_ini_get_double(ini, "key", "zone_ref_mps", 0, 0, 100, &k->zone_ref_mps, err)) < 0)
        return rc;
    if (n != 3)
        return core_err_set(err, -1, "%s: [key] station_S_m: expected three numbers", core_ini_path(ini));
    if (!strcmp(k->aircraft, "-"))
        k->aircraft[0] = '\0';
    k->rotor = (int)rotor;
    k->grid = (int)grid;
    if (k->rotor != CORE_ROTOR_LOADED)
        return 0;
    int ns = 0, ccw = 0;
    if ((rc = core_ini_get_double(ini, "key", "torque_Nm", 1, 0, 1e7, &k->torque_Nm, err)) ||
        (rc = core_ini_get_double(ini, "key", "root_cut", 1, 0, 0.5, &k->root_cut, err)) ||
        (rc = core_ini_get_bool(ini, "key", "ccw_from_above", 1, &ccw, err)) ||
        (rc = core_ini_get_doubles(ini, "key", "swirl", 1, -10, 10, k->swirl, AWDB_LOAD_NR, &ns, err)))
        return rc < 0 ? rc : -1;
    if (ns != AWDB_LOAD_NR)
        return core_err_set(err, -1, "%s: [key] swirl: expected %d numbers, got %d", core_ini_path(ini),
                            AWDB_LOAD_NR, ns);
    for (int j = 0; j < AWDB_LOAD_NPSI; j++) {
        char name[32];
        int nl = 0;
        snprintf(name, sizeof name, "load_psi%02d", j);
        if ((rc = core_ini_get_doubles(ini, "key", name, 1, -10, 10, k->load + j * AWDB_LOAD_NR, AWDB_LOAD_NR, &nl,
                                       err)))
            return rc < 0 ? rc : -1;
        if (nl != AWDB_LOAD_NR)
            return core_err_set(err, -1, "%s: [key] %s: expected %d numbers, got %d", core_ini_path(ini), name,
                                AWDB_LOAD_NR, nl);
    }
    k->ccw_from_above = ccw;
    return 0;
}

awdb *awdb_open(const char *dir, const core_log *log, core_err *err)
{
    if (strlen(dir) > AWDB_PATH - 200) {
        core_err_set(err, -1, "%s: database path too long", dir);
        return NULL;
    }
    awdb *db = calloc(1, sizeof *db);
    if (!db) {
        core_err_set(err, -1, "%s: out of memory", dir);
        return NULL;
    }
    awdb_fmt(db->dir, sizeof db->dir, "%s", dir);
    db->log = log;
    pthread_mutex_init(&db->lock, NULL);
    static const char *subs[] = {"", "fields", "queue", "running", "failed", "waiting"};
    for (int i = 0; i < 6; i++) {
        char p[AWDB_PATH];
        awdb_fmt(p, sizeof p, "%s/%s", dir, subs[i]);
        if (mkdir(p, 0777) != 0 && errno != EEXIST) {
            core_err_set(err, -1, "%s: cannot create folder: %s", p, strerror(errno));
            awdb_close(db);
            return NULL;
        }
        struct stat st;
        if (stat(p, &st) != 0 || !S_ISDIR(st.st_mode)) {
            core_err_set(err, -1, "%s: expected a folder", p);
            awdb_close(db);
            return NULL;
        }
    }
    return db;
}

void awdb_close(awdb *db)
{
    if (!db)
        return;
    pthread_mutex_destroy(&db->lock);
    free(db->cache);
    free(db);
}

const char *awdb_dir(const awdb *db) { return db->dir; }

/* awdb_file_crc64 that tells a missing file (-1) from one it could not read
 * (-2: too many open files, an I/O error): verify_field removes a field as
 * corrupt only on evidence, never because a check could not run. */
static int file_crc64(const char *path, uint64_t *crc, uint64_t *size, core_err *err)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return core_err_set(err, errno == ENOENT ? -1 : -2, "%s: cannot open: %s", path, strerror(errno));
    int bad = core_crc64_file(f, crc, size);
    fclose(f);
    if (bad)
        return core_err_set(err, -2, "%s: read error", path);
    return 0;
}

int awdb_file_crc64(const char *path, uint64_t *crc, uint64_t *size, core_err *err)
{
    return file_crc64(path, crc, size, err) ? -1 : 0;
}

/* Field files: NAME.h5 and NAME.sum ([field] size, crc64, then the key). */
static int read_sum(const char *sum_path, uint64_t *size, uint64_t *crc, awdb_key *key, core_err *err)
{
    core_ini *ini = core_ini_load(sum_path, err);
    if (!ini)
        return -1;
    int rc = awdb_sum_read(ini, size, crc, key, err);
    core_ini_destroy(ini);
    return rc;
}

int awdb_sum_read(core_ini *ini, uint64_t *size, uint64_t *crc, awdb_key *key, core_err *err)
{
    const char *sum_path = core_ini_path(ini);
    char hex[32];
    double sz = 0;
    int rc = core_ini_get_double(ini, "field", "size", 1, 0, 1e15, &sz, err);
    if (!rc)
        rc = core_ini_get_string(ini, "field", "crc64", 1, hex, sizeof hex, err);
    if (!rc && key)
        rc = awdb_key_read(ini, key, err);
    else
        core_ini_skip_section(ini, "key");
    if (!rc)
        rc = core_ini_check_unused(ini, err);
    if (rc)
        return rc < 0 ? rc : -1;
    if (sz != floor(sz))
        return core_err_set(err, -1, "%s: [field] size = %.17g: expected a whole number of bytes", sum_path, sz);
    char *end;
    *crc = strtoull(hex, &end, 16);
    if (*end || strlen(hex) != 16)
        return core_err_set(err, -1, "%s: [field] crc64 = '%s': expected 16 hex digits", sum_path, hex);
    *size = (uint64_t)sz;
    return 0;
}

/* What verify_field saw of an entry's two files when it began. */
typedef struct seen {
    int have_h5, have_sum;
    struct stat h5, sum;
} seen;

/* 1 if the field is there and its checksum holds (cached by mtime and size),
 * 0 if absent, -1 if it is there but corrupt or torn, -2 if it could not be
 * checked (no file descriptor left, an I/O error): not READY, but no
 * evidence against the field either. *sn gets what the check began with. */
static int verify_field(awdb *db, const char *name, char *path, size_t n, seen *sn)
{
    char h5[AWDB_PATH], sum[AWDB_PATH];
    awdb_path(db, h5, sizeof h5, "fields", name, ".h5");
    awdb_path(db, sum, sizeof sum, "fields", name, ".sum");
    struct stat sh, ss;
    memset(&sh, 0, sizeof sh);
    memset(&ss, 0, sizeof ss);
    int have_h5 = stat(h5, &sh) == 0, have_sum = stat(sum, &ss) == 0;
    if (sn) {
        sn->have_h5 = have_h5;
        sn->have_sum = have_sum;
        sn->h5 = sh;
        sn->sum = ss;
    }
    if (!have_h5 && !have_sum)
        return 0;
    if (!have_h5 || !have_sum) {
        core_log_msg(db->log, CORE_LOG_WARN, "%s: %s without its %s: a torn write", name,
                     have_h5 ? ".h5" : ".sum", have_h5 ? ".sum" : ".h5");
        return -1;
    }
    long long mt = (long long)sh.st_mtim.tv_sec * 1000000000LL + sh.st_mtim.tv_nsec;
    pthread_mutex_lock(&db->lock);
    for (size_t i = 0; i < db->ncache; i++)
        if (!strcmp(db->cache[i].name, name) && db->cache[i].mtime_ns == mt &&
            db->cache[i].size == (long long)sh.st_size) {
            pthread_mutex_unlock(&db->lock);
            if (path)
                awdb_fmt(path, n, "%s", h5);
            return 1;
        }
    pthread_mutex_unlock(&db->lock);
    core_err err = {0};
    uint64_t want_size, want_crc, size, crc;
    awdb_key sk;
    if (read_sum(sum, &want_size, &want_crc, &sk, &err) != 0) {
        /* Unreadable content is corruption; a .sum that cannot be opened
         * now (EMFILE, EIO) is not: the field must not be removed for it. */
        int fd = open(sum, O_RDONLY | O_CLOEXEC);
        int cannot = fd < 0 && errno != ENOENT;
        if (fd >= 0)
            close(fd);
        core_log_msg(db->log, CORE_LOG_WARN, "%s%s", err.msg, cannot ? " (cannot check it now)" : "");
        return cannot ? -2 : -1;
    }
    /* The key in the .sum is the entry's identity, the file name only its
     * hash: an entry renamed or copied under another key's name (its
     * checksum intact) would serve one wind's field for another. */
    char sname[200];
    awdb_key_name(&sk, sname, sizeof sname);
    if (strcmp(sname, name) != 0) {
        core_log_msg(db->log, CORE_LOG_WARN, "%s: its [key] is that of another entry (%s)", sum, sname);
        return -1;
    }
    int rc = file_crc64(h5, &crc, &size, &err);
    if (rc != 0) {
        core_log_msg(db->log, CORE_LOG_WARN, "%s%s", err.msg, rc == -2 ? " (cannot check it now)" : "");
        return rc == -2 ? -2 : -1;
    }
    if (size != want_size || crc != want_crc) {
        core_log_msg(db->log, CORE_LOG_WARN,
                     "%s: checksum mismatch (size %llu, crc %016llx; expected %llu, %016llx)", h5,
                     (unsigned long long)size, (unsigned long long)crc,
                     (unsigned long long)want_size, (unsigned long long)want_crc);
        return -1;
    }
    pthread_mutex_lock(&db->lock);
    if (db->ncache == db->capcache) {
        size_t cap = db->capcache ? 2 * db->capcache : 64;
        struct verified *c = realloc(db->cache, cap * sizeof *c);
        if (c) {
            db->cache = c;
            db->capcache = cap;
        }
    }
    if (db->ncache < db->capcache) {
        struct verified *v = &db->cache[db->ncache++];
        awdb_fmt(v->name, sizeof v->name, "%s", name);
        v->mtime_ns = mt;
        v->size = (long long)sh.st_size;
    }
    pthread_mutex_unlock(&db->lock);
    if (path)
        awdb_fmt(path, n, "%s", h5);
    return 1;
}

/* 1 if path is still the file st describes (have: whether it was there). */
static int same_file(const char *path, int have, const struct stat *st)
{
    struct stat now;
    int there = stat(path, &now) == 0;
    if (there != have)
        return 0;
    return !there || (now.st_dev == st->st_dev && now.st_ino == st->st_ino && now.st_size == st->st_size &&
                      now.st_mtim.tv_sec == st->st_mtim.tv_sec && now.st_mtim.tv_nsec == st->st_mtim.tv_nsec);
}

/* 1 if queue/ holds a request for name (file SEQ-NAME.req). */
static int in_queue(const awdb *db, const char *name)
{
    char q[AWDB_PATH];
    awdb_fmt(q, sizeof q, "%s/queue", db->dir);
    DIR *d = opendir(q);
    if (!d)
        return 0;
    struct dirent *e;
    int found = 0;
    size_t ln = strlen(name);
    while (!found && (e = readdir(d))) {
        const char *dash = strchr(e->d_name, '-');
        size_t l = strlen(e->d_name);
        if (dash && l > 4 && !strcmp(e->d_name + l - 4, ".req") && (size_t)(l - 4 - (dash + 1 - e->d_name)) == ln &&
            !strncmp(dash + 1, name, ln))
            found = 1;
    }
    closedir(d);
    return found;
}

static int exists(const char *p)
{
    struct stat st;
    return stat(p, &st) == 0;
}

awdb_state awdb_query(awdb *db, const awdb_key *key, char *path, size_t n)
{
    char name[200], p[AWDB_PATH], h5[AWDB_PATH], sum[AWDB_PATH];
    awdb_key_name(key, name, sizeof name);
    awdb_path(db, p, sizeof p, "running", name, ".req");
    awdb_path(db, h5, sizeof h5, "fields", name, ".h5");
    awdb_path(db, sum, sizeof sum, "fields", name, ".sum");
    int running = 0;
    for (int tries = 0;; tries++) {
        seen sn;
        int v = verify_field(db, name, path, n, &sn);
        if (v > 0)
            return AWDB_READY;
        running = exists(p);
        if (v != -1 || running)
            break;
        /* Corrupt or torn, and nobody is writing it: remove it so it is
         * rebuilt, unless a builder committed new files while it was being
         * checked (its running/ request is gone by now): those are checked
         * again, never removed unseen. */
        if (same_file(h5, sn.have_h5, &sn.h5) && same_file(sum, sn.have_sum, &sn.sum)) {
            remove(sum);
            remove(h5);
            core_log_msg(db->log, CORE_LOG_WARN, "%s: removed a corrupt field; it will be rebuilt", name);
            break;
        }
        if (tries == 2)
            break;
    }
    if (running)
        return AWDB_RUNNING;
    if (in_queue(db, name))
        return AWDB_QUEUED;
    awdb_path(db, p, sizeof p, "failed", name, ".txt");
    if (exists(p))
        return AWDB_FAILED;
    return AWDB_ABSENT;
}

int awdb_submit(awdb *db, const awdb_key *key_in, awdb_state *state, core_err *err)
{
    awdb_key key = *key_in;
    int rc = awdb_key_canon(&key, err);
    if (rc)
        return rc;
    awdb_state s = awdb_query(db, &key, NULL, 0);
    if (state)
        *state = s;
    if (s == AWDB_READY || s == AWDB_QUEUED || s == AWDB_RUNNING)
        return 0;
    char name[200], p[AWDB_PATH], seq[64], text[AWDB_KEY_TEXT];
    awdb_key_name(&key, name, sizeof name);
    if (s == AWDB_FAILED) {
        awdb_path(db, p, sizeof p, "failed", name, ".txt");
        remove(p);
    }
    /* Queue order is the file-name order: microseconds since the epoch, then pid. */
    struct timeval tv;
    gettimeofday(&tv, NULL);
    awdb_fmt(seq, sizeof seq, "%016llx%06lx-", (unsigned long long)tv.tv_sec * 1000000ULL + tv.tv_usec,
             (unsigned long)getpid() & 0xffffff);
    char file[300];
    awdb_fmt(file, sizeof file, "%s%s", seq, name);
    awdb_path(db, p, sizeof p, "queue", file, ".req");
    awdb_key_format(&key, text, sizeof text);
    return awdb_write_atomic(p, text, err);
}

/* Which faces of the CFD grid the wind enters and leaves by
 * (core_wod_faces, the rule cfd/airwake.c sets its boundaries with): a
 * small code for comparison, 9 for calm air (every face open). */
static int face_class(double speed_mps, double dir_rad)
{
    int s[2];
    if (core_wod_faces(speed_mps, dir_rad, s))
        return 9;
    return 3 * (s[0] + 1) + (s[1] + 1);
}

typedef struct warm_cand {
    char name[256];
    int grid;
    double dist, rotor;
} warm_cand;

/* the finest grid available first (the key's own before any coarser one),
 * then the nearest wind, then the nearest rotor */
static int warm_cand_cmp(const void *pa, const void *pb)
{
    const warm_cand *a = pa, *b = pb;
    if (a->grid != b->grid)
        return core_grid_rank(a->grid) > core_grid_rank(b->grid) ? -1 : 1;
    if (fabs(a->dist - b->dist) > 1e-9)
        return a->dist < b->dist ? -1 : 1;
    if (a->rotor != b->rotor)
        return a->rotor < b->rotor ? -1 : 1;
    return strcmp(a->name, b->name); /* a fixed order among equals */
}

int awdb_nearest(awdb *db, const awdb_key *key, char *path, size_t n)
{
    /* A whole-domain ship-only field starts from its own key's field on a
     * coarser grid (the finest there is), else from the inflow, never from
     * another wind's: on the CG-47's default and fine grids an oblique
     * wind's field keeps the state it started in (red 30 started from the
     * red 60 field ended 0.33 of U from red 30 started from the inflow,
     * which is green 30 reflected to 0.005; docs/validation/cfd.md). The
     * same wind's coarser field has its wake where this one's goes
     * (coarse-to-fine; a flight's quick, coarse and default fields are
     * solved in that order, docs/usage.md). */
    const int same_wind_only = key->rotor == CORE_ROTOR_OFF && !(key->zone_ref_mps > 0.0);
    char dirp[AWDB_PATH];
    awdb_fmt(dirp, sizeof dirp, "%s/fields", db->dir);
    DIR *d = opendir(dirp);
    if (!d)
        return 1;
    core_vec3 w = core_wod_vel_S_mps(key->wod_speed_mps, key->wod_dir_rad);
    /* every admissible field, best first after the scan: when the best
     * fails its checksum (a query for its own key then rebuilds it) the
     * next one still gives a warm start instead of a cold one */
    warm_cand *cand = NULL;
    size_t ncand = 0, capcand = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        size_t l = strlen(e->d_name);
        if (l < 5 || strcmp(e->d_name + l - 4, ".sum") || e->d_name[0] == '.')
            continue;
        char sum[AWDB_PATH + 300], stem[256];
        awdb_fmt(sum, sizeof sum, "%s/%s", dirp, e->d_name);
        awdb_fmt(stem, sizeof stem, "%.*s", (int)(l - 4), e->d_name);
        awdb_key k;
        uint64_t sz, crc;
        core_err err;
        if (read_sum(sum, &sz, &crc, &k, &err) != 0)
            continue;
        /* The same grid, or failing that a coarser one (coarse-to-fine: a
         * default-grid field has its wake where the coarse one put it and
         * leaves the iteration only the detail to add; SFS2 with the rotor,
         * docs/benchmarks/cfd.md). A finer grid's field is never used: the
         * coarse build would pay for resolution it cannot keep. */
        if (strcmp(k.ship, key->ship) || strcmp(k.aircraft, key->aircraft) || k.rotor != key->rotor ||
            core_grid_rank(k.grid) > core_grid_rank(key->grid) || (k.zone_ref_mps > 0.0) != (key->zone_ref_mps > 0.0))
            continue;
        if (same_wind_only && (k.grid == key->grid || k.wod_speed_mps != key->wod_speed_mps ||
                               k.wod_dir_rad != key->wod_dir_rad || k.zone_ref_mps > 0.0))
            continue;
        /* A wake 60 or 90 deg away sits elsewhere in the grid (other inflow
         * faces, the lee side moved): starting from it was seen to diverge
         * where the uniform inflow converges, so only neighbours count. */
        if (fabs(remainder(k.wod_dir_rad - key->wod_dir_rad, 2.0 * CORE_PI)) > AWDB_WARM_MAX_DIR_RAD)
            continue;
        /* Nor one whose wind enters through other faces of the grid: the
         * CFD makes a face an inlet or outlet where the wind's component
         * across it exceeds 5 % of the speed, else a symmetry plane (a
         * beam wind's fore and aft faces). CG-47 red 90 with the rotor
         * diverged from a red 60 field in all three tries and converged
         * from the inflow in 188 iterations. */
        if (face_class(k.wod_speed_mps, k.wod_dir_rad) != face_class(key->wod_speed_mps, key->wod_dir_rad))
            continue;
        core_vec3 wk = core_wod_vel_S_mps(k.wod_speed_mps, k.wod_dir_rad);
        double dist = core_vec3_norm(core_vec3_sub(w, wk));
        /* Among fields of the same wind (a coupled point's iterations), the
         * one whose rotor is nearest: the previous coupling iteration's
         * field is the best start of the next (thrust in fractions, hub in
         * radii, shaft tilt in radians). */
        double rd = 0.0;
        if (key->rotor != CORE_ROTOR_OFF) {
            rd = fabs(k.thrust_N - key->thrust_N) / fmax(key->thrust_N, 1.0) +
                 fabs(k.shaft_pitch_rad - key->shaft_pitch_rad) + fabs(k.shaft_roll_rad - key->shaft_roll_rad);
            for (int i = 0; i < 3; i++)
                rd += fabs(k.station_S_m[i] - key->station_S_m[i]) / fmax(key->radius_m, 0.1);
        }
        if (ncand == capcand) {
            size_t cap = capcand ? 2 * capcand : 16;
            warm_cand *g = realloc(cand, cap * sizeof *g);
            if (!g)
                break; /* the candidates so far still serve */
            cand = g;
            capcand = cap;
        }
        warm_cand *c = &cand[ncand++];
        c->grid = k.grid;
        c->dist = dist;
        c->rotor = rd;
        awdb_fmt(c->name, sizeof c->name, "%s", stem);
    }
    closedir(d);
    if (ncand > 1)
        qsort(cand, ncand, sizeof *cand, warm_cand_cmp);
    int rc = 1;
    for (size_t i = 0; i < ncand && rc; i++)
        if (verify_field(db, cand[i].name, path, n, NULL) > 0)
            rc = 0;
    free(cand);
    return rc;
}

static int count_dir(const awdb *db, const char *sub)
{
    char p[AWDB_PATH];
    awdb_fmt(p, sizeof p, "%s/%s", db->dir, sub);
    DIR *d = opendir(p);
    if (!d)
        return 0;
    int c = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        size_t l = strlen(e->d_name);
        if (l > 4 && !strcmp(e->d_name + l - 4, ".req"))
            c++;
    }
    closedir(d);
    return c;
}

/* waiting/NAME.PID of this process */
static int wait_path(awdb *db, const awdb_key *key, char *out, size_t n)
{
    awdb_key k = *key;
    core_err e = {0};
    if (awdb_key_canon(&k, &e) != 0)
        return -1;
    char name[AWDB_NAME_MAX];
    awdb_key_name(&k, name, sizeof name);
    return awdb_fmt(out, n, "%s/waiting/%s.%ld", db->dir, name, (long)getpid()) < 0 ? -1 : 0;
}

int awdb_wait_mark(awdb *db, const awdb_key *key, core_err *err)
{
    char p[AWDB_PATH + 32];
    if (wait_path(db, key, p, sizeof p) != 0)
        return core_err_set(err, -1, "airwake database %s: a wait mark for an invalid key", db->dir);
    int fd = open(p, O_WRONLY | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0)
        return core_err_set(err, -1, "%s: cannot create: %s", p, strerror(errno));
    close(fd);
    return 0;
}

void awdb_wait_unmark(awdb *db, const awdb_key *key)
{
    char p[AWDB_PATH + 32];
    if (wait_path(db, key, p, sizeof p) == 0)
        remove(p);
}

int awdb_builder_alive(awdb *db)
{
    char p[AWDB_PATH];
    awdb_fmt(p, sizeof p, "%s/builder.lock", db->dir);
    int fd = open(p, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return 0;
    /* The builder holds an exclusive lock for its lifetime: if we can take
     * a shared one, nobody serves the database. Shared, so that two clients
     * probing at once do not take each other for a builder (a builder
     * starting meanwhile waits the probe out: awdb_builder_run). */
    int alive = flock(fd, LOCK_SH | LOCK_NB) != 0;
    if (!alive)
        flock(fd, LOCK_UN);
    close(fd);
    return alive;
}

int awdb_pending(awdb *db, int *queued, int *running)
{
    *queued = count_dir(db, "queue");
    *running = count_dir(db, "running");
    return 0;
}

/* ------------------------------------------------------------- progress */
/* One running/NAME.prog (builder.c writes it): 1 read, 0 absent or not
 * whole (a file from before a power cut: the rename is not synced). */
static int read_run_progress(const awdb *db, awdb_run_progress *r)
{
    char path[AWDB_PATH];
    if (awdb_fmt(path, sizeof path, "%s/running/%s.prog", db->dir, r->name) < 0)
        return 0;
    core_err err = {0};
    core_ini *ini = core_ini_load(path, &err);
    if (!ini)
        return 0;
    long it = 0, max = 0;
    int ok = core_ini_get_int(ini, "progress", "iteration", 1, 0, 1000000000L, &it, &err) == 0 &&
             core_ini_get_int(ini, "progress", "max_iterations", 1, 0, 1000000000L, &max, &err) == 0 &&
             core_ini_get_double(ini, "progress", "residual", 1, 0, 1e300, &r->residual, &err) == 0 &&
             core_ini_get_double(ini, "progress", "fraction", 1, 0, 1e6, &r->frac, &err) == 0 &&
             core_ini_get_double(ini, "progress", "elapsed_s", 1, 0, 1e12, &r->elapsed_s, &err) == 0 &&
             core_ini_get_double(ini, "progress", "left_s", 1, -1, 1e12, &r->left_s, &err) == 0;
    core_ini_destroy(ini);
    r->iteration = (int)it;
    r->max_iterations = (int)max;
    return ok;
}

static int cmp_run(const void *a, const void *b)
{
    return strcmp(((const awdb_run_progress *)a)->name, ((const awdb_run_progress *)b)->name);
}

int awdb_progress_read(awdb *db, awdb_progress *out, core_err *err)
{
    memset(out, 0, sizeof *out);
    /* queue/, running/, fields/: the order a request moves in, so that one
     * moving on during the read counts in two places, never in none */
    out->queued = count_dir(db, "queue");
    char p[AWDB_PATH];
    awdb_fmt(p, sizeof p, "%s/running", db->dir);
    DIR *d = opendir(p);
    if (!d)
        return core_err_set(err, -1, "%s: cannot read: %s", p, strerror(errno));
    /* Every running request, the first AWDB_PROGRESS_MAX_RUNS by name kept
     * (a fixed choice, so a display does not hop between builds). */
    awdb_run_progress *runs = out->runs;
    struct dirent *e;
    while ((e = readdir(d))) {
        size_t l = strlen(e->d_name);
        if (l < 5 || strcmp(e->d_name + l - 4, ".req") || l - 4 >= AWDB_NAME_MAX)
            continue;
        out->running++;
        awdb_run_progress r;
        memset(&r, 0, sizeof r);
        awdb_fmt(r.name, sizeof r.name, "%.*s", (int)(l - 4), e->d_name);
        int k = out->n_runs;
        if (k == AWDB_PROGRESS_MAX_RUNS) { /* full: replace the last by name if this one comes before */
            if (strcmp(r.name, runs[k - 1].name) >= 0)
                continue;
            k--;
        } else {
            out->n_runs++;
        }
        runs[k] = r;
        qsort(runs, (size_t)out->n_runs, sizeof *runs, cmp_run);
    }
    closedir(d);
    awdb_fmt(p, sizeof p, "%s/fields", db->dir);
    if (!(d = opendir(p)))
        return core_err_set(err, -1, "%s: cannot read: %s", p, strerror(errno));
    while ((e = readdir(d))) {
        size_t l = strlen(e->d_name);
        /* an entry counts with its checksum file; "NAME.sum.part" is a
         * commit under way */
        if (e->d_name[0] != '.' && l > 4 && !strcmp(e->d_name + l - 4, ".sum"))
            out->ready++;
    }
    closedir(d);
    for (int i = 0; i < out->n_runs; i++) {
        runs[i].left_s = -1.0;
        runs[i].have = read_run_progress(db, &runs[i]);
        if (!runs[i].have) {
            runs[i].iteration = runs[i].max_iterations = 0;
            runs[i].residual = runs[i].frac = runs[i].elapsed_s = 0.0;
            runs[i].left_s = -1.0;
        }
    }
    out->builder_alive = awdb_builder_alive(db);
    return 0;
}

const awdb_run_progress *awdb_progress_find(const awdb_progress *p, const char *name)
{
    for (int i = 0; i < p->n_runs; i++)
        if (!strcmp(p->runs[i].name, name))
            return &p->runs[i];
    return NULL;
}

int awdb_list(awdb *db, awdb_list_fn fn, void *user, core_err *err)
{
    char p[AWDB_PATH];
    awdb_fmt(p, sizeof p, "%s/fields", db->dir);
    DIR *d = opendir(p);
    if (!d)
        return core_err_set(err, -1, "%s: cannot read: %s", p, strerror(errno));
    struct dirent *e;
    int n = 0;
    while ((e = readdir(d))) {
        size_t l = strlen(e->d_name);
        if (l < 5 || strcmp(e->d_name + l - 4, ".sum") || l - 4 >= AWDB_NAME_MAX)
            continue;
        char sp[AWDB_PATH];
        awdb_fmt(sp, sizeof sp, "%s/%s", p, e->d_name);
        uint64_t size, crc;
        awdb_key k;
        core_err e2 = {0};
        if (read_sum(sp, &size, &crc, &k, &e2) != 0)
            continue; /* a torn or foreign entry: not a field */
        n++;
        if (fn(user, &k))
            break;
    }
    closedir(d);
    return n;
}
