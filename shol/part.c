/* part.c -- a sweep dealt over several processes (ranks): each rank sweeps
 * the directions dealt to it and writes its envelopes as a part file into
 * a stage folder that every rank can reach; rank 0 gathers the parts into
 * the envelopes a serial run would have made (docs/cluster.md).
 *
 * A part holds the structs as they are in memory (a shol_dir_result and
 * its samples), so every rank must run the same build of disim on the
 * same kind of machine; the part's header records the struct sizes and
 * the byte order, and a part that does not match is refused. Each part is
 * written under a temporary name in the stage folder and renamed into
 * place (shol/io.c), so rank 0 never reads half a part. */
#include "io.h"
#include "shol.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define PART_MAGIC "disim-shol-part 1\n"
#define PART_END "end\n"

int shol_settings_deal(const shol_settings *all, int rank, int ranks, shol_settings *mine, core_err *err)
{
    if (ranks < 1 || rank < 0 || rank >= ranks)
        return core_err_set(err, -1, "shol: rank %d of %d: expected 0 <= rank < ranks", rank, ranks);
    *mine = *all;
    mine->n_dirs = 0;
    for (int i = rank; i < all->n_dirs; i += ranks)
        mine->dirs_rad[mine->n_dirs++] = all->dirs_rad[i];
    return mine->n_dirs;
}

static void part_paths(const char *stage, int rank, const char *ext, char *final, size_t n)
{
    snprintf(final, n, "%s/part-%d%s", stage, rank, ext);
}

/* ------------------------------------------------------------------ write */
static void put_i32(FILE *f, int32_t v) { fwrite(&v, sizeof v, 1, f); }

static void put_text(FILE *f, const char *s)
{
    uint32_t n = s ? (uint32_t)strlen(s) : UINT32_MAX;
    fwrite(&n, sizeof n, 1, f);
    if (s)
        fwrite(s, 1, n, f);
}

static void put_result(FILE *f, const shol_result *r)
{
    put_i32(f, r ? 1 : 0);
    if (!r)
        return;
    put_i32(f, r->n_dirs);
    put_i32(f, r->n_trims);
    fwrite(&r->wall_s, sizeof r->wall_s, 1, f);
    fwrite(&r->band_rule, sizeof r->band_rule, 1, f);
    fwrite(r->band_grid_label, sizeof r->band_grid_label, 1, f);
    fwrite(r->band_model_label, sizeof r->band_model_label, 1, f);
    for (int i = 0; i < r->n_dirs; i++) {
        fwrite(&r->dirs[i], sizeof r->dirs[i], 1, f);
        if (r->dirs[i].n_samples > 0)
            fwrite(r->dirs[i].samples, sizeof *r->dirs[i].samples, (size_t)r->dirs[i].n_samples, f);
    }
}

/* The header: magic, the struct sizes and byte order, rank, ranks, key. */
static void put_header(FILE *f, int rank, int ranks, const char *key)
{
    fputs(PART_MAGIC, f);
    put_i32(f, 0x01020304);
    put_i32(f, (int32_t)sizeof(shol_dir_result));
    put_i32(f, (int32_t)sizeof(shol_sample));
    put_i32(f, rank);
    put_i32(f, ranks);
    put_text(f, key);
}

int shol_part_write(const char *stage, int rank, int ranks, const char *key, const shol_result *r1,
                    const shol_result *r2, const char *const texts[SHOL_PART_TEXTS], core_err *err)
{
    char name[64], final[SHOL_IO_PATH_MAX], tmp[SHOL_IO_PATH_MAX];
    snprintf(name, sizeof name, "part-%d", rank);
    if (shol_io_mkdir(stage, err) != 0 || shol_io_paths(stage, name, final, tmp, err) != 0)
        return -1;
    FILE *f = shol_io_open(tmp, err);
    if (!f)
        return -1;
    put_header(f, rank, ranks, key);
    put_result(f, r1);
    put_result(f, r2);
    for (int k = 0; k < SHOL_PART_TEXTS; k++)
        put_text(f, texts ? texts[k] : NULL);
    fputs(PART_END, f);
    return shol_io_commit(f, tmp, final, err);
}

int shol_part_fail(const char *stage, int rank, const char *why)
{
    char name[64], final[SHOL_IO_PATH_MAX], tmp[SHOL_IO_PATH_MAX];
    core_err e = {0};
    snprintf(name, sizeof name, "part-%d.failed", rank);
    if (shol_io_mkdir(stage, &e) != 0 || shol_io_paths(stage, name, final, tmp, &e) != 0)
        return -1;
    FILE *f = shol_io_open(tmp, &e);
    if (!f)
        return -1;
    fprintf(f, "%s\n", why);
    return shol_io_commit(f, tmp, final, &e);
}

/* ------------------------------------------------------------------- read */
typedef struct part {
    shol_result r[2];
    int have[2];
    char *texts[SHOL_PART_TEXTS];
} part;

static void part_free(part *p)
{
    for (int k = 0; k < 2; k++)
        shol_result_free(&p->r[k]);
    for (int k = 0; k < SHOL_PART_TEXTS; k++)
        free(p->texts[k]);
    memset(p, 0, sizeof *p);
}

static int get(FILE *f, void *buf, size_t n) { return fread(buf, 1, n, f) == n ? 0 : -1; }

/* A text (*out NULL for none); < 0 on a short or oversized read. */
static int get_text(FILE *f, char **out)
{
    uint32_t n;
    *out = NULL;
    if (get(f, &n, sizeof n) != 0)
        return -1;
    if (n == UINT32_MAX)
        return 0;
    if (n > (1u << 28) || !(*out = malloc((size_t)n + 1)))
        return -1;
    if (get(f, *out, n) != 0)
        return -1;
    (*out)[n] = '\0';
    return 0;
}

static int get_result(FILE *f, shol_result *r, int *have)
{
    int32_t present, n, nt;
    memset(r, 0, sizeof *r);
    if (get(f, &present, sizeof present) != 0)
        return -1;
    *have = present != 0;
    if (!present)
        return 0;
    if (get(f, &n, sizeof n) != 0 || get(f, &nt, sizeof nt) != 0 || n < 0 || n > SHOL_MAX_DIRS)
        return -1;
    r->n_trims = nt;
    if (get(f, &r->wall_s, sizeof r->wall_s) != 0 || get(f, &r->band_rule, sizeof r->band_rule) != 0 ||
        get(f, r->band_grid_label, sizeof r->band_grid_label) != 0 ||
        get(f, r->band_model_label, sizeof r->band_model_label) != 0)
        return -1;
    r->band_grid_label[sizeof r->band_grid_label - 1] = '\0';
    r->band_model_label[sizeof r->band_model_label - 1] = '\0';
    if (n == 0)
        return 0;
    if (!(r->dirs = calloc((size_t)n, sizeof *r->dirs)))
        return -1;
    for (int i = 0; i < n; i++) {
        shol_dir_result *d = &r->dirs[i];
        if (get(f, d, sizeof *d) != 0) {
            d->samples = NULL;
            r->n_dirs = i;
            return -1;
        }
        d->samples = NULL;
        r->n_dirs = i + 1;
        if (d->n_samples < 0 || d->n_samples > 1000000)
            return -1;
        if (d->n_samples == 0)
            continue;
        if (!(d->samples = malloc((size_t)d->n_samples * sizeof *d->samples)) ||
            get(f, d->samples, (size_t)d->n_samples * sizeof *d->samples) != 0)
            return -1;
    }
    return 0;
}

/* Rank's part from path: 0, or < 0 with err saying what does not match. */
static int part_read(const char *path, int rank, int ranks, const char *key, part *p, core_err *err)
{
    memset(p, 0, sizeof *p);
    FILE *f = fopen(path, "rb");
    if (!f)
        return core_err_set(err, -1, "%s: cannot read: %s", path, strerror(errno));
    char magic[sizeof PART_MAGIC] = "", end[sizeof PART_END] = "";
    int32_t h[5];
    char *k = NULL;
    int rc = -1;
    if (get(f, magic, strlen(PART_MAGIC)) != 0 || strcmp(magic, PART_MAGIC) != 0 || get(f, h, sizeof h) != 0) {
        core_err_set(err, -1, "%s: not a part of disim shol", path);
        goto out;
    }
    if (h[0] != 0x01020304 || h[1] != (int32_t)sizeof(shol_dir_result) || h[2] != (int32_t)sizeof(shol_sample)) {
        core_err_set(err, -1, "%s: written by another build of disim or another kind of machine", path);
        goto out;
    }
    if (h[3] != rank || h[4] != ranks || get_text(f, &k) != 0 || !k || strcmp(k, key) != 0) {
        core_err_set(err, -1, "%s: a part of another run (rank %d of %d%s)", path, h[3], h[4],
                     k && strcmp(k, key) ? ", other settings" : "");
        goto out;
    }
    for (int i = 0; i < 2; i++)
        if (get_result(f, &p->r[i], &p->have[i]) != 0) {
            core_err_set(err, -1, "%s: cut short or damaged", path);
            goto out;
        }
    for (int i = 0; i < SHOL_PART_TEXTS; i++)
        if (get_text(f, &p->texts[i]) != 0) {
            core_err_set(err, -1, "%s: cut short or damaged", path);
            goto out;
        }
    if (get(f, end, strlen(PART_END)) != 0 || strcmp(end, PART_END) != 0) {
        core_err_set(err, -1, "%s: cut short or damaged", path);
        goto out;
    }
    rc = 0;
out:
    free(k);
    fclose(f);
    if (rc != 0)
        part_free(p);
    return rc;
}

static void sleep_s(double s)
{
    struct timespec ts = {(time_t)s, (long)((s - floor(s)) * 1e9)};
    nanosleep(&ts, NULL);
}

/* Wait for rank's part (or its failure) and read it: 0, or < 0 with err
 * naming the rank that failed or did not come within timeout_s. */
static int part_wait(const char *stage, int rank, int ranks, const char *key, double t_end, part *p, core_err *err)
{
    char path[SHOL_IO_PATH_MAX], failed[SHOL_IO_PATH_MAX];
    part_paths(stage, rank, "", path, sizeof path);
    part_paths(stage, rank, ".failed", failed, sizeof failed);
    for (;;) {
        struct stat st;
        if (stat(failed, &st) == 0) {
            char why[768] = "";
            FILE *f = fopen(failed, "r");
            if (f) {
                if (!fgets(why, sizeof why, f))
                    why[0] = '\0';
                fclose(f);
            }
            why[strcspn(why, "\n")] = '\0';
            return core_err_set(err, -1, "rank %d of %d failed: %s", rank, ranks, why[0] ? why : "(no reason given)");
        }
        if (stat(path, &st) == 0)
            return part_read(path, rank, ranks, key, p, err);
        if (core_monotonic_s() >= t_end)
            return core_err_set(err, -1, "rank %d of %d: no part in %s within the wait (--rank-wait-s)", rank, ranks,
                                stage);
        sleep_s(0.2);
    }
}

/* dst = the whole envelope from each rank's own (src[r], the directions
 * shol_settings_deal gave rank r), in all's order. */
static int merge(const shol_settings *all, int ranks, shol_result *const *src, shol_result *dst, core_err *err)
{
    memset(dst, 0, sizeof *dst);
    dst->settings = *all;
    if (!(dst->dirs = calloc((size_t)all->n_dirs, sizeof *dst->dirs)))
        return core_err_set(err, -1, "shol: out of memory");
    dst->n_dirs = all->n_dirs;
    for (int r = 0; r < ranks; r++) {
        int want = all->n_dirs / ranks + (r < all->n_dirs % ranks);
        if (src[r]->n_dirs != want)
            return core_err_set(err, -1, "rank %d: %d directions, expected %d", r, src[r]->n_dirs, want);
        dst->n_trims += src[r]->n_trims;
        dst->wall_s = fmax(dst->wall_s, src[r]->wall_s);
    }
    for (int i = 0; i < all->n_dirs; i++) {
        shol_dir_result *d = &src[i % ranks]->dirs[i / ranks];
        if (d->dir_rad != all->dirs_rad[i])
            return core_err_set(err, -1, "rank %d: direction %g deg where %g deg was dealt", i % ranks,
                                d->dir_rad * CORE_RAD_TO_DEG, all->dirs_rad[i] * CORE_RAD_TO_DEG);
        dst->dirs[i] = *d;
        d->samples = NULL; /* moved */
        d->n_samples = 0;
    }
    /* the bands' rule and labels: the same on every rank */
    dst->band_rule = src[0]->band_rule;
    memcpy(dst->band_grid_label, src[0]->band_grid_label, sizeof dst->band_grid_label);
    memcpy(dst->band_model_label, src[0]->band_model_label, sizeof dst->band_model_label);
    return 0;
}

int shol_part_gather(const char *stage, int ranks, const char *key, const shol_settings *all, double timeout_s,
                     shol_result *r1, shol_result *r2, char **texts, core_err *err)
{
    if (ranks < 1 || ranks > SHOL_MAX_RANKS)
        return core_err_set(err, -1, "shol: %d ranks: expected 1 to %d", ranks, SHOL_MAX_RANKS);
    part *p = calloc((size_t)ranks, sizeof *p);
    shol_result **s1 = calloc((size_t)ranks, sizeof *s1), **s2 = calloc((size_t)ranks, sizeof *s2);
    int rc = -1;
    if (!p || !s1 || !s2) {
        core_err_set(err, -1, "shol: out of memory");
        goto out;
    }
    double t_end = core_monotonic_s() + timeout_s;
    s1[0] = r1;
    s2[0] = r2;
    for (int r = 1; r < ranks; r++) {
        if (part_wait(stage, r, ranks, key, t_end, &p[r], err) != 0)
            goto out;
        if (!p[r].have[0] || p[r].have[1] != (r2 != NULL)) {
            core_err_set(err, -1, "rank %d: its part holds %s envelope", r, p[r].have[1] ? "a two-way" : "no two-way");
            goto out;
        }
        s1[r] = &p[r].r[0];
        s2[r] = &p[r].r[1];
    }
    shol_result m1, m2;
    memset(&m2, 0, sizeof m2);
    if (merge(all, ranks, s1, &m1, err) != 0) {
        shol_result_free(&m1);
        goto out;
    }
    if (r2 && merge(all, ranks, s2, &m2, err) != 0) {
        shol_result_free(&m1);
        shol_result_free(&m2);
        goto out;
    }
    shol_result_free(r1);
    *r1 = m1;
    if (r2) {
        shol_result_free(r2);
        *r2 = m2;
    }
    for (int r = 1; r < ranks; r++)
        for (int k = 0; k < SHOL_PART_TEXTS; k++) {
            if (texts)
                texts[r * SHOL_PART_TEXTS + k] = p[r].texts[k];
            else
                free(p[r].texts[k]);
            p[r].texts[k] = NULL;
        }
    rc = 0;
out:
    for (int r = 1; p && r < ranks; r++)
        part_free(&p[r]);
    free(p);
    free(s1);
    free(s2);
    return rc;
}

void shol_part_clean(const char *stage, int ranks)
{
    char path[SHOL_IO_PATH_MAX];
    for (int r = 0; r < ranks; r++) {
        part_paths(stage, r, "", path, sizeof path);
        unlink(path);
        part_paths(stage, r, ".failed", path, sizeof path);
        unlink(path);
    }
    rmdir(stage);
}
