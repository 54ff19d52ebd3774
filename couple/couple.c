/* couple.c -- the coupling loop (seed paper section 2.5); see couple.h for
 * the model. Assumptions, beyond the seed paper's:
 *  - The actuator disk carries the trim's blade loads (hfm_rotor_disk: the
 *    blade-element thrust and in-plane force per unit area over 8 radial x
 *    12 azimuthal cells, resampled to the database key's table) with the
 *    trim's thrust, at the trimmed hub, tilted with the trimmed shaft; the
 *    uniform disk of eq. 5 is an option. Keys round thrust to 1 N, tilt to
 *    0.1 deg and the load shape to 0.001 of its mean, so a converged loop
 *    re-reads its last field.
 *  - "Change less than 5 %" is measured per quantity as |dx| / max(|x|, f)
 *    with floors f = 10 % of travel for controls and 1 deg for attitudes, so
 *    quantities near zero do not demand impossible relative accuracy.
 *  - The isolated-rotor field for the interaction velocity is the same case
 *    with the ship's cells left open (ship name + ".isolated").
 *  - Option (settings.zone): both fields cover the deck zone only, the
 *    coupled one bounded by the ship-only field scaled to the speed (see
 *    cfd/airwake.c for that model's assumptions), and the interaction gets
 *    the difference between the whole domain's ship-only airwake and the
 *    zone's own (zone_correction), so that the zone adds only what the
 *    rotor changes.
 *  - From the second coupled iteration on, the interaction velocity is
 *    under-relaxed: half this iteration's fields, half the previous ones
 *    (a plain fixed-point iteration oscillated where the interaction is
 *    strong).
 *  - Over the rotor disk the interaction velocity is projected on the
 *    inflow modes of the flight model's Pitt-Peters model (uniform and
 *    first harmonics, linear in r; Peters and HaQuang 1988): the blade
 *    elements see the disk-scale interaction, not the pointwise difference
 *    of two slipstream edges a cell wide (disk_fit). Fuselage, tail rotor
 *    and empennage see the pointwise field.
 */
#include "couple.h"
#include "cfd.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define CACHE_N 8
/* seed a coupled point with the interaction of one at most this far in
 * speed (a point trimmed again at the same speed is not seeded: it starts
 * from free air as before and re-reads its fields) */
#define SEED_MAX_DV_MPS 3.0
/* seeds kept: one per direction, a full circle in 5 deg steps */
#define SEED_DIRS 72

/* The interaction velocity, under-relaxed: weight w on this iteration's
 * fields and 1 - w on the previous iteration's (prev_coupled NULL: none). */
typedef struct air_interaction {
    const cfd_field *coupled, *isolated;
    const cfd_field *prev_coupled, *prev_isolated;
    double w;
    double wind[3];
    /* the interaction over the rotor disk, projected on the Pitt-Peters
     * modes (see disk_fit): v_k(r, psi) = m[k] + (r/R)(c[k] cos psi +
     * s[k] sin psi), psi from the hub frame's x axis */
    double hub[3], R;
    core_quat q_SH;
    double m[3], c[3], s[3];
    /* deck zone: corr_scale (ship_whole - ship_zone), the whole domain's
     * ship-only airwake in place of the zone's own (NULL: none) */
    const cfd_field *ship_whole, *ship_zone;
    double corr_scale;
} air_interaction;

struct couple_ctx {
    const hfm_aircraft *ac;
    const core_ship *ship;
    awdb *db;
    couple_settings s;
    const core_log *log;
    hfm_trim *trim;
    hfm_disk *disk;
    struct {
        char path[1024];
        cfd_field *f;
        unsigned long used;
    } cache[CACHE_N];
    unsigned long tick;
    hfm_trim_result last;   /* warm start for the next trim */
    int have_last;
    couple_point *hist;
    int nhist, caphist;
    char last_error[1024];
    pid_t builder_pid;
    couple_field_info *fields;
    int nfields, capfields;
    /* The interaction of the last coupled point of each direction (the
     * next speed's seed there): its air with the field pointers cleared
     * (the cache may drop the fields) and the fields' database paths (""
     * where ai has none). One per direction: the envelope sweeps every
     * direction before it walks any down, and a walk-down's first point
     * is seeded from its own direction's last point, as in a run of that
     * direction alone (the same trims, hence the same database keys). */
    struct seed_slot {
        int valid;
        double v, dir;
        unsigned long used;
        air_interaction ai;
        char coupled[1024], isolated[1024], prev_coupled[1024], prev_isolated[1024];
    } seeds[SEED_DIRS];
    unsigned long seed_tick;
};

/* The seed of a direction, or NULL. */
static struct seed_slot *seed_find(couple_ctx *c, double dir)
{
    for (int i = 0; i < SEED_DIRS; i++)
        if (c->seeds[i].valid && fabs(c->seeds[i].dir - dir) < 1e-9)
            return &c->seeds[i];
    return NULL;
}

/* The slot for a direction's seed: its own, a free one or the least
 * recently stored. */
static struct seed_slot *seed_slot_for(couple_ctx *c, double dir)
{
    struct seed_slot *s = seed_find(c, dir);
    if (s)
        return s;
    int lru = 0;
    for (int i = 0; i < SEED_DIRS; i++) {
        if (!c->seeds[i].valid)
            return &c->seeds[i];
        if (c->seeds[i].used < c->seeds[lru].used)
            lru = i;
    }
    return &c->seeds[lru];
}

void couple_settings_default(couple_settings *s)
{
    memset(s, 0, sizeof *s);
    s->mode = COUPLE_TWO_WAY;
    s->grid = AWDB_GRID_DEFAULT;
    s->max_iter = 6;
    s->tol_frac = 0.05;
    s->ref_speed_mps = 15.0;
    s->station_S_m[2] = -6.0;
    s->wait_timeout_s = 3 * 3600.0;
    s->seed_from_previous = 1;
    s->seed_one_way = 1;
}

couple_ctx *couple_create(const hfm_aircraft *ac, const core_ship *ship, awdb *db,
                          const couple_settings *s, const core_log *log, core_err *err)
{
    if (s->max_iter < 1 || s->max_iter > COUPLE_MAX_ITER) {
        core_err_set(err, -1, "coupling: max_iter = %d: expected 1 to %d", s->max_iter, COUPLE_MAX_ITER);
        return NULL;
    }
    if (s->zone && s->direct && s->mode == COUPLE_TWO_WAY) {
        core_err_set(err, -1, "coupling: the deck zone (zone = 1) works with the interaction velocity only, not "
                              "with the coupled field used directly (direct = 1)");
        return NULL;
    }
    if (!(s->tol_frac > 0.0 && s->tol_frac < 1.0) || !(s->ref_speed_mps > 0.0)) {
        core_err_set(err, -1, "coupling: tol_frac in (0, 1) and ref_speed_mps > 0 expected");
        return NULL;
    }
    couple_ctx *c = calloc(1, sizeof *c);
    if (!c) {
        core_err_set(err, -1, "coupling: out of memory");
        return NULL;
    }
    c->ac = ac;
    c->ship = ship;
    c->db = db;
    c->s = *s;
    c->log = log;
    c->trim = hfm_trim_create(ac, log);
    c->disk = malloc(sizeof *c->disk);
    if (!c->trim || !c->disk) {
        core_err_set(err, -1, "coupling: out of memory");
        couple_destroy(c);
        return NULL;
    }
    return c;
}

void couple_destroy(couple_ctx *c)
{
    if (!c)
        return;
    for (int i = 0; i < CACHE_N; i++)
        cfd_field_destroy(c->cache[i].f);
    hfm_trim_destroy(c->trim);
    free(c->disk);
    free(c->hist);
    free(c->fields);
    if (c->builder_pid > 0)
        waitpid(c->builder_pid, NULL, WNOHANG);
    free(c);
}

/* Start `disim airwaked DB --exit-when-idle` in the background, its output
 * into DB/builder.log. */
static void spawn_builder(couple_ctx *c)
{
    if (!c->s.disim_exe || !c->s.ships_dir)
        return;
    if (c->builder_pid > 0 && waitpid(c->builder_pid, NULL, WNOHANG) == 0)
        return; /* ours is still starting up */
    pid_t pid = fork();
    if (pid == 0) {
        char logp[1100];
        snprintf(logp, sizeof logp, "%s/builder.log", awdb_dir(c->db));
        int fd = open(logp, O_WRONLY | O_CREAT | O_APPEND, 0666);
        if (fd >= 0) {
            dup2(fd, 1);
            dup2(fd, 2);
            close(fd);
        }
        setsid(); /* outlives this process if another client still waits */
        char it[32];
        snprintf(it, sizeof it, "%d", c->s.cfd_max_iter);
        if (c->s.cfd_max_iter > 0)
            execl(c->s.disim_exe, c->s.disim_exe, "airwaked", awdb_dir(c->db), "--exit-when-idle", "--ships",
                  c->s.ships_dir, "--no-lcm", "--max-iter", it, (char *)NULL);
        else
            execl(c->s.disim_exe, c->s.disim_exe, "airwaked", awdb_dir(c->db), "--exit-when-idle", "--ships",
                  c->s.ships_dir, "--no-lcm", (char *)NULL);
        _exit(127);
    }
    if (pid > 0) {
        c->builder_pid = pid;
        core_log_msg(c->log, CORE_LOG_INFO, "started an airwake builder (pid %ld)", (long)pid);
    }
}

/* Record a loaded field's solver state once (for couple_fields); out of
 * memory only loses the record. */
static void note_field(couple_ctx *c, const char *path, const cfd_field *f)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    size_t len = strlen(base);
    if (len > 3 && !strcmp(base + len - 3, ".h5"))
        len -= 3;
    for (int i = 0; i < c->nfields; i++)
        if (strlen(c->fields[i].name) == len && !strncmp(c->fields[i].name, base, len))
            return;
    if (c->nfields == c->capfields) {
        int cap = c->capfields ? 2 * c->capfields : 16;
        couple_field_info *p = realloc(c->fields, (size_t)cap * sizeof *p);
        if (!p)
            return;
        c->fields = p;
        c->capfields = cap;
    }
    const cfd_meta *m = cfd_field_meta(f);
    couple_field_info *fi = &c->fields[c->nfields++];
    memset(fi, 0, sizeof *fi);
    snprintf(fi->name, sizeof fi->name, "%.*s", (int)(len < sizeof fi->name ? len : sizeof fi->name - 1), base);
    fi->wod_speed_mps = m->wod_speed_mps;
    fi->wod_dir_deg = m->wod_dir_deg;
    snprintf(fi->rotor, sizeof fi->rotor, "%s", m->rotor);
    fi->iterations = m->result.iterations;
    fi->converged = m->result.converged;
    fi->averaged = m->result.averaged;
    fi->steady_mean = m->result.steady_mean;
    fi->mean_drift = m->result.mean_drift;
    fi->mean_change = m->result.mean_change;
    fi->residual_continuity = m->result.residual[0];
    fi->mirrored = m->mirrored;
}

const couple_field_info *couple_fields(const couple_ctx *c, int *n)
{
    *n = c->nfields;
    return c->fields;
}

static const cfd_field *load_cached(couple_ctx *c, const char *path, core_err *err)
{
    int lru = 0;
    for (int i = 0; i < CACHE_N; i++) {
        if (c->cache[i].f && !strcmp(c->cache[i].path, path)) {
            c->cache[i].used = ++c->tick;
            return c->cache[i].f;
        }
        if (c->cache[i].used < c->cache[lru].used)
            lru = i;
    }
    cfd_field *f = cfd_field_load(path, err);
    if (!f)
        return NULL;
    note_field(c, path, f);
    cfd_field_destroy(c->cache[lru].f);
    c->cache[lru].f = f;
    snprintf(c->cache[lru].path, sizeof c->cache[lru].path, "%s", path);
    c->cache[lru].used = ++c->tick;
    return f;
}

/* The database path of a loaded field (NULL: not in the cache). */
static const char *cached_path(const couple_ctx *c, const cfd_field *f)
{
    for (int i = 0; i < CACHE_N; i++)
        if (f && c->cache[i].f == f)
            return c->cache[i].path;
    return NULL;
}

/* The field for key: from the database, or queued and waited for. */
static const cfd_field *get_field(couple_ctx *c, awdb_key *key, core_err *err)
{
    if (awdb_key_canon(key, err))
        return NULL;
    char path[1024], name[200];
    awdb_key_name(key, name, sizeof name);
    struct timespec t0, now;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    int announced = 0;
    for (;;) {
        awdb_state st = awdb_query(c->db, key, path, sizeof path);
        if (st == AWDB_READY)
            return load_cached(c, path, err);
        if (st == AWDB_FAILED) {
            core_err_set(err, -1, "airwake %s failed to build (see %s/failed/%s.txt)", name, awdb_dir(c->db), name);
            return NULL;
        }
        if (st == AWDB_ABSENT && awdb_submit(c->db, key, NULL, err) != 0)
            return NULL;
        if (!announced) {
            core_log_msg(c->log, CORE_LOG_INFO, "waiting for airwake %s", name);
            announced = 1;
        }
        if (!awdb_builder_alive(c->db)) {
            if (!c->s.disim_exe) {
                core_err_set(err, -1, "airwake %s is not in %s and no builder serves it (start `disim airwaked %s`)",
                             name, awdb_dir(c->db), awdb_dir(c->db));
                return NULL;
            }
            spawn_builder(c);
        }
        clock_gettime(CLOCK_MONOTONIC, &now);
        double waited_s = (double)(now.tv_sec - t0.tv_sec) + 1e-9 * (double)(now.tv_nsec - t0.tv_nsec);
        if (c->s.wait_fn)
            c->s.wait_fn(c->s.wait_user, key, waited_s);
        if (waited_s > c->s.wait_timeout_s) {
            core_err_set(err, -1, "airwake %s: still not built after %.0f s", name, c->s.wait_timeout_s);
            return NULL;
        }
        if (c->builder_pid > 0)
            waitpid(c->builder_pid, NULL, WNOHANG);
        struct timespec ts = {0, 200000000};
        nanosleep(&ts, NULL);
    }
}

/* ---------------------------------------------------------- air sources */
/* The pointwise interaction velocity (coupled - isolated), under-relaxed
 * against the previous iteration's. */
static int interaction_at(const air_interaction *a, const double pos[3], double out[3])
{
    double c[CFD_NVARS], i[CFD_NVARS], pc[CFD_NVARS], pi[CFD_NVARS];
    int rc = cfd_field_sample(a->coupled, pos, c);
    int ri = cfd_field_sample(a->isolated, pos, i);
    double w = a->prev_coupled ? a->w : 1.0;
    if (a->prev_coupled) {
        cfd_field_sample(a->prev_coupled, pos, pc);
        cfd_field_sample(a->prev_isolated, pos, pi);
    }
    for (int k = 0; k < 3; k++)
        out[k] = w * (c[k] - i[k]) + (a->prev_coupled ? (1.0 - w) * (pc[k] - pi[k]) : 0.0);
    if (a->ship_zone) {
        double sw[CFD_NVARS], sz[CFD_NVARS];
        cfd_field_sample(a->ship_whole, pos, sw);
        cfd_field_sample(a->ship_zone, pos, sz);
        for (int k = 0; k < 3; k++)
            out[k] += a->corr_scale * (sw[k] - sz[k]);
    }
    return (rc > 0 || ri > 0) ? 1 : (rc < 0 ? rc : ri);
}

/* Where the disk's projected interaction applies: within 1.1 R of the
 * shaft and 0.3 R of the disk plane (flapping blades stay inside). Sets
 * r/R and psi. */
static int in_disk(const air_interaction *a, const double pos[3], double *rr, double *psi)
{
    core_vec3 d = core_vec3_make(pos[0] - a->hub[0], pos[1] - a->hub[1], pos[2] - a->hub[2]);
    core_vec3 h = core_quat_rotate_inv(a->q_SH, d);
    double r = sqrt(h.x * h.x + h.y * h.y);
    if (r > 1.1 * a->R || fabs(h.z) > 0.3 * a->R)
        return 0;
    *rr = r / a->R;
    *psi = atan2(h.y, h.x);
    return 1;
}

/* Project the interaction over the disk on the modes of the flight model's
 * own inflow model (Pitt-Peters: uniform and the two first harmonics,
 * linear in r), by area-weighted least squares on a polar grid over 0.2 R
 * to R. Why: pointwise, the difference of two resolved slipstreams is
 * dominated at the blade tips by the slipstream edge, which sits within
 * a cell or two of the tip and moves by a fraction of a cell between the
 * coupled and the isolated solution. On a flat deck in calm air (hub 0.95 R
 * above the deck) the pointwise difference was 0.5-0.7 m/s downward at
 * r = 0.9-0.95 R and 0.5-1.5 m/s upward inboard; the trim, loaded at the
 * tips, took 5 % more collective in ground effect. The projection keeps
 * the disk-scale interaction (ground effect, the airwake's up- and
 * downwash, its gradients) and drops the tip-cell noise; the fuselage,
 * tail and empennage still see the pointwise field. */
static void disk_fit(air_interaction *a, const hfm_disk *d, double R)
{
    memcpy(a->hub, d->hub_S_m, sizeof a->hub);
    a->q_SH = d->q_SH;
    a->R = R;
    double sm[3] = {0}, sc[3] = {0}, ss[3] = {0}, w0 = 0, wc = 0, ws = 0;
    const int nr = 16, np = 36;
    for (int ir = 0; ir < nr; ir++) {
        double x = 0.2 + 0.8 * (ir + 0.5) / nr; /* r/R */
        for (int ip = 0; ip < np; ip++) {
            double psi = 2.0 * M_PI * (ip + 0.5) / np;
            core_vec3 hp = core_vec3_make(x * R * cos(psi), x * R * sin(psi), 0.0);
            core_vec3 sp = core_quat_rotate(a->q_SH, hp);
            double pos[3] = {a->hub[0] + sp.x, a->hub[1] + sp.y, a->hub[2] + sp.z}, v[3];
            interaction_at(a, pos, v);
            double wt = x; /* area element r dr dpsi */
            double cc = x * cos(psi), sn = x * sin(psi);
            for (int k = 0; k < 3; k++) {
                sm[k] += wt * v[k];
                sc[k] += wt * v[k] * cc;
                ss[k] += wt * v[k] * sn;
            }
            w0 += wt;
            wc += wt * cc * cc;
            ws += wt * sn * sn;
        }
    }
    for (int k = 0; k < 3; k++) {
        a->m[k] = sm[k] / w0;
        a->c[k] = sc[k] / wc;
        a->s[k] = ss[k] / ws;
    }
}

static int air_interaction_fn(void *user, const double pos[3], double t, double vel[3])
{
    (void)t;
    air_interaction *a = user;
    double rr, psi;
    if (in_disk(a, pos, &rr, &psi)) {
        for (int k = 0; k < 3; k++)
            vel[k] = a->wind[k] + a->m[k] + rr * (a->c[k] * cos(psi) + a->s[k] * sin(psi));
        return 0;
    }
    double v[3];
    int rc = interaction_at(a, pos, v);
    for (int k = 0; k < 3; k++)
        vel[k] = a->wind[k] + v[k];
    return rc;
}

static void base_key(couple_ctx *c, awdb_key *k, double v, double dir)
{
    memset(k, 0, sizeof *k);
    snprintf(k->ship, sizeof k->ship, "%s", c->ship->name);
    snprintf(k->aircraft, sizeof k->aircraft, "%s", hfm_aircraft_name(c->ac));
    k->wod_speed_mps = v;
    k->wod_dir_rad = dir;
    k->grid = c->s.grid;
}

/* Linear interpolation in a radial-major table t[i * np + j] of the flight
 * model's disk at radius r (clamped to the cell centres) and azimuth index
 * position y (periodic; cell j is centred at j + 0.5). */
static double disk_sample(const hfm_disk *d, const double *t, double r, double y)
{
    int i0 = 0;
    while (i0 < d->nr - 2 && d->r_m[i0 + 1] < r)
        i0++;
    int i1 = d->nr > 1 ? i0 + 1 : i0;
    double fr = d->nr > 1 ? (r - d->r_m[i0]) / (d->r_m[i1] - d->r_m[i0]) : 0.0;
    fr = fmin(fmax(fr, 0.0), 1.0);
    double x = y - 0.5;
    x -= floor(x / d->npsi) * d->npsi;
    int j0 = (int)floor(x) % d->npsi, j1 = (j0 + 1) % d->npsi;
    double fp = x - floor(x);
    double a = (1 - fr) * t[i0 * d->npsi + j0] + fr * t[i1 * d->npsi + j0];
    double b = (1 - fr) * t[i0 * d->npsi + j1] + fr * t[i1 * d->npsi + j1];
    return (1 - fp) * a + fp * b;
}

int couple_key_set_rotor(const hfm_aircraft *ac, const hfm_disk *d, int loaded, awdb_key *k)
{
    if (!(d->thrust_N > 0.0) || d->nr < 1 || d->npsi < 4)
        return -1;
    core_euler sh = core_quat_to_euler(d->q_SH);
    double R = hfm_aircraft_rotor_radius_m(ac);
    k->rotor = loaded ? AWDB_ROTOR_LOADED : AWDB_ROTOR_UNIFORM;
    k->thrust_N = d->thrust_N;
    memcpy(k->station_S_m, d->hub_S_m, sizeof k->station_S_m);
    k->radius_m = R;
    k->shaft_pitch_rad = sh.theta_rad;
    k->shaft_roll_rad = sh.phi_rad;
    if (!loaded)
        return 0;
    /* cells of the flight model's disk run from the root cut to the tip */
    double dr = d->nr > 1 ? d->r_m[1] - d->r_m[0] : 2.0 * (R - d->r_m[0]);
    double root = fmax(d->r_m[0] - 0.5 * dr, 0.0);
    k->root_cut = fmin(root / R, 0.5);
    k->ccw_from_above = d->sense > 0;
    double wsum = 0.0, lsum = 0.0, smax = 0.0;
    for (int i = 0; i < AWDB_LOAD_NR; i++) {
        double r = (i + 0.5) / AWDB_LOAD_NR * R;
        double sw = 0.0;
        for (int j = 0; j < AWDB_LOAD_NPSI; j++) {
            double y = (double)j * d->npsi / AWDB_LOAD_NPSI;
            double l = r < root ? 0.0 : disk_sample(d, d->thrust_Pa, r, y);
            k->load[j * AWDB_LOAD_NR + i] = l;
            lsum += l * r;
            sw += r < root ? 0.0 : disk_sample(d, d->swirl_Pa, r, y);
        }
        wsum += r * AWDB_LOAD_NPSI;
        k->swirl[i] = sw / AWDB_LOAD_NPSI;
        smax = fmax(smax, fabs(k->swirl[i]));
    }
    if (!(lsum > 0.0))
        return -1;
    double mean = lsum / wsum; /* area-weighted mean pressure jump */
    for (int i = 0; i < AWDB_LOAD_NR * AWDB_LOAD_NPSI; i++)
        k->load[i] /= mean;
    for (int i = 0; i < AWDB_LOAD_NR; i++)
        k->swirl[i] = smax > 0.0 ? k->swirl[i] / smax : 0.0;
    /* the in-plane forces' moment about the shaft: the rotor torque */
    double q = 0.0, dpsi = 2.0 * CORE_PI / d->npsi;
    for (int i = 0; i < d->nr; i++)
        for (int j = 0; j < d->npsi; j++)
            q += d->swirl_Pa[i * d->npsi + j] * d->r_m[i] * d->r_m[i] * dr * dpsi;
    k->torque_Nm = fmax(q, 0.0);
    return 0;
}

int couple_free_air_rotor(const hfm_aircraft *ac, const double station_S_m[3], double v, double dir, int loaded,
                          awdb_key *key, core_err *err)
{
    hfm_trim *t = hfm_trim_create(ac, NULL);
    hfm_disk *d = malloc(sizeof *d);
    if (!t || !d) {
        hfm_trim_destroy(t);
        free(d);
        return core_err_set(err, -1, "free-air trim: out of memory");
    }
    hfm_trim_cond cond;
    memset(&cond, 0, sizeof cond);
    cond.kind = HFM_TRIM_HOVER_SHIP;
    cond.wod_speed_mps = v;
    cond.wod_dir_rad = dir;
    memcpy(cond.pos_S_m, station_S_m, sizeof cond.pos_S_m);
    hfm_trim_result r;
    int rc = hfm_trim_solve(t, &cond, NULL, &r);
    if (rc == 0) {
        hfm_air_uniform uni;
        core_vec3 w = core_wod_vel_S_mps(v, dir);
        uni.vel_S_mps[0] = w.x, uni.vel_S_mps[1] = w.y, uni.vel_S_mps[2] = w.z;
        hfm_air air = {hfm_air_uniform_fn, &uni, NULL};
        if (hfm_rotor_disk(ac, &air, 0.0, &r.body, &r.u, &r.rotor, 8, 12, d) != 0 ||
            couple_key_set_rotor(ac, d, loaded, key) != 0)
            rc = core_err_set(err, -1, "free-air trim at %.2f m/s from %.1f deg: rotor disk evaluation failed", v,
                              dir * CORE_RAD_TO_DEG);
    } else if (rc > 0) {
        core_err_set(err, rc, "free-air trim at %.2f m/s from %.1f deg did not converge", v, dir * CORE_RAD_TO_DEG);
    } else {
        core_err_set(err, rc, "free-air trim at %.2f m/s from %.1f deg: fatal error", v, dir * CORE_RAD_TO_DEG);
    }
    hfm_trim_destroy(t);
    free(d);
    return rc;
}

/* The relative change of a control or attitude, against at least `floor`.
 * The floors are the smallest margins the rejection criteria leave
 * (CONVENTIONS.md): 20 % of travel (the pedal's) for a control, 5 deg (the
 * roll limit) for an attitude, so 5 % is 1 % of travel or 0.25 deg near
 * zero. Why not less: a control's percentage has an arbitrary origin (pedal
 * 9.7 % is 90.3 % from the other stop), and with floors of 10 % and 1 deg a
 * point near a stop kept iterating on changes of 0.6 % of travel and 0.09
 * deg, below what the averaged fields resolve (CG-47 red 60 at 50 km/h:
 * six coupled iterations, the last two moving pedal 10.4 -> 9.8 -> 9.7 %). */
static double change(double a, double b, double floor)
{
    return fabs(a - b) / fmax(fmax(fabs(a), fabs(b)), floor);
}

static void record(couple_iter *it, const hfm_trim_result *r, const couple_iter *prev)
{
    it->thrust_N = r->loads.mr_thrust_N;
    it->collective_pct = r->u.collective_pct;
    it->long_pct = r->u.long_pct;
    it->lat_pct = r->u.lat_pct;
    it->pedal_pct = r->u.pedal_pct;
    it->phi_rad = r->body.euler_rad[0];
    it->theta_rad = r->body.euler_rad[1];
    it->change_frac = NAN;
    if (prev) {
        const double fc = 20.0, fa = 5.0 * CORE_DEG_TO_RAD;
        double m = change(it->collective_pct, prev->collective_pct, fc);
        m = fmax(m, change(it->long_pct, prev->long_pct, fc));
        m = fmax(m, change(it->lat_pct, prev->lat_pct, fc));
        m = fmax(m, change(it->pedal_pct, prev->pedal_pct, fc));
        m = fmax(m, change(it->phi_rad, prev->phi_rad, fa));
        m = fmax(m, change(it->theta_rad, prev->theta_rad, fa));
        it->change_frac = m;
    }
}

static int solve(couple_ctx *c, const hfm_trim_cond *cond, hfm_trim_result *res)
{
    int rc = hfm_trim_solve(c->trim, cond, c->have_last ? &c->last : NULL, res);
    if (rc == 1 && c->have_last) /* a cold start sometimes finds what the warm one missed */
        rc = hfm_trim_solve(c->trim, cond, NULL, res);
    if (rc == 0) {
        c->last = *res;
        c->have_last = 1;
    }
    return rc;
}

/* The one-way air at a WOD: the direction's ship-only field (at the
 * reference speed) scaled to v. 0, or -1 with err when the field cannot be
 * had. The field stays in the cache until the next fetch. */
static int ship_only_air(couple_ctx *c, double v, double dir, cfd_field_scaled *a, core_err *err)
{
    awdb_key k;
    base_key(c, &k, c->s.ref_speed_mps, dir);
    k.rotor = AWDB_ROTOR_OFF;
    a->field = get_field(c, &k, err);
    a->scale = v / c->s.ref_speed_mps;
    return a->field ? 0 : -1;
}

/* Deck zone: the whole domain's and the zone's own ship-only fields of the
 * direction, for the correction ship_whole - ship_zone (both scale with the
 * speed). Why: the coupled zone field holds the zone's version of the ship
 * airwake, which is not the whole domain's where the wake is unsteady (CG-47
 * red 60 on the coarse grid: 10 m/s apart over the spot with no rotor);
 * corrected, the zone contributes only what the rotor changes, and a rotor
 * without thrust gives the one-way air exactly. The zone's ship-only field
 * is placed at the CG station (not at each trim's hub), so one serves a
 * direction. */
static void zone_ship_key(couple_ctx *c, double dir, awdb_key *k)
{
    base_key(c, k, c->s.ref_speed_mps, dir);
    k->rotor = AWDB_ROTOR_OFF;
    k->zone_ref_mps = c->s.ref_speed_mps;
    memcpy(k->station_S_m, c->s.station_S_m, sizeof k->station_S_m);
    k->radius_m = hfm_aircraft_rotor_radius_m(c->ac);
}

static int zone_correction(couple_ctx *c, double v, double dir, air_interaction *ai, core_err *err)
{
    ai->ship_whole = ai->ship_zone = NULL;
    if (!c->s.zone || !(v > 0.0))
        return 0;
    awdb_key k;
    zone_ship_key(c, dir, &k);
    const cfd_field *sz = get_field(c, &k, err);
    if (!sz)
        return -1;
    cfd_field_scaled so;
    if (ship_only_air(c, v, dir, &so, err) != 0)
        return -1;
    /* the whole field's fetch may have evicted the zone's: fetch it again */
    if (!(sz = get_field(c, &k, err)))
        return -1;
    ai->ship_whole = so.field;
    ai->ship_zone = sz;
    ai->corr_scale = v / c->s.ref_speed_mps;
    return 0;
}

int couple_trim(couple_ctx *c, double v, double dir, couple_point *p, core_err *err)
{
    memset(p, 0, sizeof *p);
    p->wod_speed_mps = v;
    p->wod_dir_rad = dir;
    hfm_trim_cond cond;
    memset(&cond, 0, sizeof cond);
    cond.kind = HFM_TRIM_HOVER_SHIP;
    cond.wod_speed_mps = v;
    cond.wod_dir_rad = dir;
    memcpy(cond.pos_S_m, c->s.station_S_m, sizeof cond.pos_S_m);

    if (c->s.mode == COUPLE_ONE_WAY) {
        /* calm air: the ship-only field scaled by v is zero everywhere, so
         * the one-way trim is the free-air one and needs no field */
        cfd_field_scaled a;
        hfm_air air = {cfd_field_air_scaled, &a, NULL};
        if (v > 0.0) {
            if (ship_only_air(c, v, dir, &a, err) != 0)
                return -1;
            cond.air = &air;
        }
        int rc = solve(c, &cond, &p->trim);
        if (rc < 0)
            return core_err_set(err, rc, "trim at %.2f m/s from %.1f deg: fatal error", v, dir * CORE_RAD_TO_DEG);
        p->converged = rc == 0;
        p->coupling_converged = 1;
        p->n_iter = 1;
        record(&p->iter[0], &p->trim, NULL);
        return rc;
    }

    hfm_air_uniform uni;
    core_vec3 w = core_wod_vel_S_mps(v, dir);
    uni.vel_S_mps[0] = w.x;
    uni.vel_S_mps[1] = w.y;
    uni.vel_S_mps[2] = w.z;
    hfm_air free_air = {hfm_air_uniform_fn, &uni, NULL};
    /* The air of the latest trim; it outlives each iteration because the next
     * disk is evaluated in it (before any field is fetched, so the cached
     * fields it points to are still loaded). */
    air_interaction ai;
    memset(&ai, 0, sizeof ai);
    cfd_field_scaled direct;
    hfm_air air = {NULL, NULL, NULL};

    /* Iteration 0: the trim in the interaction of the previous coupled
     * point of this direction (seed_from_previous), else in free air. Why:
     * from free air the first coupled trim always moved more than 5 %, so
     * every speed took two coupled and two isolated fields; the interaction
     * changes little over one speed step, and a trim seeded with it is
     * usually within 5 % of the trim in its own fields after one pair. The
     * first coupled iteration takes the new fields whole (no relaxation),
     * so a point that converges there is trimmed in its own fields only. */
    int rc = 1;
    const struct seed_slot *sd = seed_find(c, dir);
    if (c->s.seed_from_previous && !c->s.direct && sd && fabs(sd->v - v) <= SEED_MAX_DV_MPS &&
        fabs(sd->v - v) > 1e-6) {
        /* four fields in a cache of CACHE_N: none evicts another */
        ai = sd->ai;
        int ok = (ai.coupled = load_cached(c, sd->coupled, err)) != NULL &&
                 (ai.isolated = load_cached(c, sd->isolated, err)) != NULL;
        if (ok && sd->prev_coupled[0])
            ok = (ai.prev_coupled = load_cached(c, sd->prev_coupled, err)) != NULL &&
                 (ai.prev_isolated = load_cached(c, sd->prev_isolated, err)) != NULL;
        if (ok && zone_correction(c, v, dir, &ai, err) != 0)
            return -1;
        if (!ok) { /* a field gone from the database: start in free air */
            memset(&ai, 0, sizeof ai);
        } else {
            memcpy(ai.wind, uni.vel_S_mps, sizeof ai.wind);
            air.fn = air_interaction_fn;
            air.user = &ai;
            air.wake = &free_air; /* the flight model's wake is the isolated rotor's (hfm.h) */
            cond.air = &air;
            rc = solve(c, &cond, &p->trim);
            if (rc < 0)
                return core_err_set(err, rc, "seeded trim at %.2f m/s: fatal error", v);
            if (rc == 0) {
                p->seed = COUPLE_SEED_PREVIOUS;
                p->seed_speed_mps = sd->v;
            }
            else
                cond.air = NULL;
        }
    }
    /* A point with no previous coupled point to seed it: the one-way trim.
     * Why: the ship-only airwake holds most of what moves the trim away
     * from free air (CG-47 red 60: one-way pedal 70 % at 60 km/h, free-air
     * pedal 39 % at 50 km/h), so the first coupled disk, loaded from it,
     * is nearer the coupled solution. The scaled field stays in the cache
     * while the first disk is evaluated in it (nothing is fetched before). */
    cfd_field_scaled ship_air;
    hfm_air ship_hfm_air = {cfd_field_air_scaled, &ship_air, NULL};
    if (rc != 0 && c->s.seed_one_way && !c->s.direct && v > 0.0) { /* calm: the scaled field is free air */
        if (ship_only_air(c, v, dir, &ship_air, err) != 0)
            return -1;
        cond.air = &ship_hfm_air;
        rc = solve(c, &cond, &p->trim);
        if (rc < 0)
            return core_err_set(err, rc, "one-way seed trim at %.2f m/s: fatal error", v);
        if (rc == 0)
            p->seed = COUPLE_SEED_ONE_WAY;
        else
            cond.air = NULL;
    }
    if (rc != 0) {
        rc = solve(c, &cond, &p->trim);
        if (rc != 0) {
            if (rc < 0)
                return core_err_set(err, rc, "free-air trim at %.2f m/s: fatal error", v);
            p->converged = 0;
            return 1;
        }
    }
    record(&p->iter[0], &p->trim, NULL);
    p->n_iter = 1;
    for (int it = 1; it < c->s.max_iter + 1 && it < COUPLE_MAX_ITER; it++) {
        /* The disk from the current trim, evaluated in the air it was trimmed in. */
        const hfm_air *air_now = cond.air ? cond.air : &free_air;
        if (hfm_rotor_disk(c->ac, air_now, 0.0, &p->trim.body, &p->trim.u, &p->trim.rotor, 8, 12, c->disk) != 0)
            return core_err_set(err, -1, "rotor disk at %.2f m/s from %.1f deg: evaluation failed", v, dir * CORE_RAD_TO_DEG);
        awdb_key kc;
        base_key(c, &kc, v, dir);
        if (couple_key_set_rotor(c->ac, c->disk, !c->s.uniform_disk, &kc) != 0)
            return core_err_set(err, -1, "rotor disk at %.2f m/s from %.1f deg: no thrust", v, dir * CORE_RAD_TO_DEG);
        if (c->s.zone && v > 0.0) {
            /* the zone's boundary must be in the database before the zone
             * is built (it usually is: the one-way trim used it) */
            kc.zone_ref_mps = c->s.ref_speed_mps;
            awdb_key kb;
            awdb_key_zone_boundary(&kc, &kb);
            if (!get_field(c, &kb, err))
                return -1;
            /* the zone's own ship-only field (zone_correction), queued now
             * to be built beside the first pair */
            awdb_key kz;
            zone_ship_key(c, dir, &kz);
            if (awdb_submit(c->db, &kz, NULL, err) != 0)
                return -1;
        }
        awdb_key ki = kc;
        snprintf(ki.ship, sizeof ki.ship, "%s.isolated", c->ship->name);
        if (!c->s.direct) {
            /* queue the isolated rotor now, so that a builder with two jobs
             * runs it beside the coupled field */
            if (awdb_key_canon(&ki, err) != 0 || awdb_submit(c->db, &ki, NULL, err) != 0)
                return -1;
        }
        const cfd_field *fc = get_field(c, &kc, err);
        if (!fc)
            return -1;
        direct.field = fc;
        direct.scale = 1.0;
        if (c->s.direct) {
            air.fn = cfd_field_air_scaled;
            air.user = &direct;
        } else {
            const cfd_field *fi = get_field(c, &ki, err);
            if (!fi)
                return -1;
            /* get_field may have evicted fc from the cache: fetch it again. */
            fc = get_field(c, &kc, err);
            if (!fc)
                return -1;
            /* The fixed-point iteration trim -> CFD -> trim overshoots where
             * the interaction is strong (the collective was seen to swing
             * +-10 % between iterations): each iteration takes half of the
             * new interaction and half of the previous one. */
            ai.prev_coupled = it > 1 ? ai.coupled : NULL;
            ai.prev_isolated = it > 1 ? ai.isolated : NULL;
            ai.w = 0.5;
            ai.coupled = fc;
            ai.isolated = fi;
            /* after fc and fi: six fields in a cache of CACHE_N */
            if (zone_correction(c, v, dir, &ai, err) != 0)
                return -1;
            memcpy(ai.wind, uni.vel_S_mps, sizeof ai.wind);
            disk_fit(&ai, c->disk, hfm_aircraft_rotor_radius_m(c->ac));
            air.fn = air_interaction_fn;
            air.user = &ai;
            air.wake = &free_air; /* the flight model's wake is the isolated rotor's (hfm.h) */
        }
        cond.air = &air;
        hfm_trim_result next;
        rc = solve(c, &cond, &next);
        if (rc != 0) {
            if (rc < 0)
                return core_err_set(err, rc, "coupled trim at %.2f m/s: fatal error", v);
            p->converged = 0;
            return 1;
        }
        p->trim = next;
        record(&p->iter[it], &p->trim, &p->iter[it - 1]);
        p->n_iter = it + 1;
        if (p->iter[it].change_frac < c->s.tol_frac) {
            p->coupling_converged = 1;
            break;
        }
    }
    p->converged = 1;
    if (!c->s.direct) {
        /* keep this point's interaction as the seed of the next speed */
        const char *pc = cached_path(c, ai.coupled), *pi = cached_path(c, ai.isolated);
        const char *ppc = ai.prev_coupled ? cached_path(c, ai.prev_coupled) : "";
        const char *ppi = ai.prev_isolated ? cached_path(c, ai.prev_isolated) : "";
        struct seed_slot *ss = seed_slot_for(c, dir);
        ss->valid = pc && pi && ppc && ppi;
        if (ss->valid) {
            ss->v = v;
            ss->dir = dir;
            ss->used = ++c->seed_tick;
            snprintf(ss->coupled, sizeof ss->coupled, "%s", pc);
            snprintf(ss->isolated, sizeof ss->isolated, "%s", pi);
            snprintf(ss->prev_coupled, sizeof ss->prev_coupled, "%s", ppc);
            snprintf(ss->prev_isolated, sizeof ss->prev_isolated, "%s", ppi);
            ss->ai = ai;
            ss->ai.coupled = ss->ai.isolated = ss->ai.prev_coupled = ss->ai.prev_isolated = NULL;
        }
    }
    if (!p->coupling_converged)
        core_log_msg(c->log, CORE_LOG_WARN, "coupling at %.2f m/s from %.1f deg: change %.1f %% after %d iterations",
                     v, dir * CORE_RAD_TO_DEG, 100.0 * p->iter[p->n_iter - 1].change_frac, p->n_iter - 1);
    return 0;
}

int couple_prefetch(couple_ctx *c, const double *dirs, int n, core_err *err)
{
    int missing = 0;
    for (int i = 0; i < n; i++) {
        awdb_key k;
        awdb_state st;
        base_key(c, &k, c->s.ref_speed_mps, dirs[i]);
        k.rotor = AWDB_ROTOR_OFF;
        if (awdb_submit(c->db, &k, &st, err) != 0)
            return -1;
        missing += st != AWDB_READY;
    }
    if (missing && c->s.disim_exe && !awdb_builder_alive(c->db))
        spawn_builder(c);
    return 0;
}

int couple_shol_trim(void *user, double v, double dir, shol_trim_point *out)
{
    couple_ctx *c = user;
    if (c->nhist == c->caphist) {
        int cap = c->caphist ? 2 * c->caphist : 64;
        couple_point *h = realloc(c->hist, cap * sizeof *h);
        if (!h) {
            snprintf(c->last_error, sizeof c->last_error, "coupling: out of memory");
            return -1;
        }
        c->hist = h;
        c->caphist = cap;
    }
    couple_point *p = &c->hist[c->nhist];
    core_err err = {{0}};
    int rc = couple_trim(c, v, dir, p, &err);
    if (rc < 0) {
        snprintf(c->last_error, sizeof c->last_error, "%s", err.msg);
        return -1;
    }
    c->nhist++;
    if (rc > 0 || !p->converged)
        return 1;
    out->phi_rad = p->trim.body.euler_rad[0];
    out->theta_rad = p->trim.body.euler_rad[1];
    out->collective_pct = p->trim.u.collective_pct;
    out->long_cyclic_pct = p->trim.u.long_pct;
    out->lat_cyclic_pct = p->trim.u.lat_pct;
    out->pedal_pct = p->trim.u.pedal_pct;
    return 0;
}

const couple_point *couple_history(const couple_ctx *c, int *n)
{
    *n = c->nhist;
    return c->hist;
}

const char *couple_last_error(const couple_ctx *c) { return c->last_error; }

/* The report's field table. Why each flag: an unconverged field is the
 * mean of its last iterations (cfd.h avg_window); its mean_drift and
 * mean_change say how far that mean still moves (within its window, and
 * from the window before); a continuity residual above 1 means the mass
 * imbalance grew past the run's first iterations, which the solver's
 * divergence test (1e4) lets pass. */
char *couple_fields_md(const couple_field_info *f1, int n1, const couple_field_info *f2, int n2)
{
    core_str md = {0};
    int nconv = 0, navg = 0, ngrew = 0, nmir = 0;
    for (int i = 0; i < n1 + n2; i++) {
        const couple_field_info *fi = i < n1 ? &f1[i] : &f2[i - n1];
        nmir += fi->mirrored;
        nconv += fi->converged;
        navg += fi->averaged > 0;
        ngrew += !fi->converged && fi->residual_continuity > 1.0;
    }
    core_str_printf(&md,
                    "%d fields, %d converged (residuals below 1e-4 and deck-line monitors changing less than "
                    "2 %% of the WOD speed per 50 iterations), %d not converged and averaged over their last "
                    "iterations (an unconverged field is the mean of its limit cycle; docs/validation/cfd.md; "
                    "\"steady mean\": the run stopped before its iteration cap once the means over the two "
                    "halves of its last window, and that window's mean and the mean of the window before "
                    "it, agreed at the deck monitors within 2 %% of the WOD speed; before solver 0.5.0 the "
                    "halves alone). Trims in unconverged fields are less certain than the others; \"mean "
                    "drift\" and \"mean change\" say how much: the largest difference between the deck "
                    "monitors' mean velocities over the two halves of the averaging window, and between "
                    "the window and the one before it (\"-\": none before it), in %% of the WOD speed (a "
                    "steady mean is below 2 %% in both).\n\n",
                    n1 + n2, nconv, navg);
    if (nmir)
        core_str_printf(&md,
                        "%d field%s the mirror image of the opposite direction's (the ship is symmetric about "
                        "its centre line; \"mirror of\" in the state; iterations and residuals are the "
                        "solved field's).\n\n",
                        nmir, nmir > 1 ? "s are" : " is");
    /* Continuity is divided by its largest value over a run's first five
     * iterations: above 1 at the end, the mass imbalance grew (CG-47 green
     * 90 on the default grid ended at 68 with its monitors settled), and
     * the divergence test (1e4) does not stop it. */
    if (ngrew)
        core_str_printf(&md,
                        "**%d field%s ended with a continuity residual above 1**: the mass imbalance grew "
                        "beyond that of the run's first iterations, even where its monitors settled. Trims in "
                        "%s are the least certain of all.\n\n",
                        ngrew, ngrew > 1 ? "s" : "", ngrew > 1 ? "them" : "it");
    core_str_printf(&md,
                    "| field | WOD speed (m/s) | WOD dir (deg) | rotor | iterations | state | continuity "
                    "| mean drift (%% of U) | mean change (%% of U) |\n"
                    "|---|---|---|---|---|---|---|---|---|\n");
    for (int i = 0; i < n1 + n2; i++) {
        const couple_field_info *fi = i < n1 ? &f1[i] : &f2[i - n1];
        char st[128] = "";
        size_t sl = 0;
        if (fi->mirrored)
            sl = (size_t)snprintf(st, sizeof st, "mirror of %.1f: ", core_wod_mirror_deg(fi->wod_dir_deg));
        if (fi->converged)
            snprintf(st + sl, sizeof st - sl, "converged");
        else if (fi->averaged && fi->steady_mean)
            snprintf(st + sl, sizeof st - sl, "steady mean of last %d", fi->averaged);
        else if (fi->averaged)
            snprintf(st + sl, sizeof st - sl, "not converged, mean of last %d", fi->averaged);
        else
            snprintf(st + sl, sizeof st - sl, "not converged");
        if (!fi->converged && fi->residual_continuity > 1.0) {
            size_t l = strlen(st);
            snprintf(st + l, sizeof st - l, "; continuity grew");
        }
        char drift[24] = "-", change[24] = "-";
        if (fi->averaged && fi->mean_drift > 0.0)
            snprintf(drift, sizeof drift, "%.1f", 100.0 * fi->mean_drift);
        if (fi->averaged && fi->mean_change >= 0.0)
            snprintf(change, sizeof change, "%.1f", 100.0 * fi->mean_change);
        core_str_printf(&md, "| %s | %.2f | %.1f | %s | %d | %s | %.1e | %s | %s |\n", fi->name,
                        fi->wod_speed_mps, fi->wod_dir_deg, fi->rotor, fi->iterations, st, fi->residual_continuity,
                        drift, change);
    }
    return core_str_take(&md);
}
