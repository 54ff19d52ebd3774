/* io.c -- output folder and atomic writes (write a temporary file in the
 * same folder, then rename: rename within one file system is atomic). */
#include "io.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <math.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int shol_io_mkdir(const char *dir, core_err *err)
{
    if (!dir || !*dir)
        return core_err_set(err, -1, "shol: empty output folder name");
    if (strlen(dir) >= SHOL_IO_PATH_MAX)
        return core_err_set(err, -1, "%s: output folder name too long", dir);
    return core_mkdir_p(dir, err);
}

/* Every plain file in stage (not a name starting with '.'), called with
 * its name; stops at the first call that returns non-zero. */
static int stage_each(const char *stage, int (*fn)(const char *stage, const char *name, void *u), void *u)
{
    DIR *d = opendir(stage);
    if (!d)
        return -1;
    int rc = 0;
    for (struct dirent *e; !rc && (e = readdir(d));)
        if (e->d_name[0] != '.')
            rc = fn(stage, e->d_name, u);
    closedir(d);
    return rc;
}

static int remove_one(const char *stage, const char *name, void *u)
{
    (void)u;
    char p[SHOL_IO_PATH_MAX + 256];
    snprintf(p, sizeof p, "%s/%s", stage, name);
    unlink(p);
    return 0;
}

void shol_io_stage_abort(const char *stage)
{
    if (!stage || !stage[0])
        return;
    stage_each(stage, remove_one, NULL);
    DIR *d = opendir(stage); /* the writers' own temporaries, ".NAME.tmp.PID" */
    if (d) {
        for (struct dirent *e; (e = readdir(d));)
            if (strcmp(e->d_name, ".") && strcmp(e->d_name, ".."))
                remove_one(stage, e->d_name, NULL);
        closedir(d);
    }
    rmdir(stage);
}

int shol_io_stage_begin(const char *dir, char *stage, core_err *err)
{
    stage[0] = '\0';
    if (shol_io_mkdir(dir, err) < 0)
        return -1;
    int n = snprintf(stage, SHOL_IO_PATH_MAX, "%s/.shol.stage.%ld", dir, (long)getpid());
    if (n < 0 || n >= SHOL_IO_PATH_MAX) {
        stage[0] = '\0';
        return core_err_set(err, -1, "%s: output folder name too long", dir);
    }
    shol_io_stage_abort(stage); /* one left by a killed run of the same pid */
    if (mkdir(stage, 0777) < 0) {
        core_err_set(err, -1, "%s: cannot create the output folder's staging folder: %s", stage, strerror(errno));
        stage[0] = '\0';
        return -1;
    }
    return 0;
}

typedef struct stage_ctx {
    const char *dir;
    core_err *err;
} stage_ctx;

static int target_ok(const char *stage, const char *name, void *u)
{
    (void)stage;
    stage_ctx *c = u;
    char p[SHOL_IO_PATH_MAX + 256];
    snprintf(p, sizeof p, "%s/%s", c->dir, name);
    return core_output_check(p, c->err) != 0;
}

static int move_one(const char *stage, const char *name, void *u)
{
    stage_ctx *c = u;
    char from[SHOL_IO_PATH_MAX + 256], to[SHOL_IO_PATH_MAX + 256];
    snprintf(from, sizeof from, "%s/%s", stage, name);
    snprintf(to, sizeof to, "%s/%s", c->dir, name);
    if (rename(from, to) < 0)
        return core_err_set(c->err, -1, "%s: cannot rename into place: %s", to, strerror(errno)), 1;
    return 0;
}

int shol_io_stage_commit(const char *dir, const char *stage, core_err *err)
{
    stage_ctx c = {dir, err};
    /* every target first: a folder or a device where a file goes stops
     * the set before any of it is moved */
    if (stage_each(stage, target_ok, &c) != 0 || stage_each(stage, move_one, &c) != 0) {
        shol_io_stage_abort(stage);
        return -1;
    }
    rmdir(stage);
    core_sync_path(dir);
    return 0;
}

int shol_io_paths(const char *dir, const char *name, char *final, char *tmp, core_err *err)
{
    int n1 = snprintf(final, SHOL_IO_PATH_MAX, "%s/%s", dir, name);
    int n2 = snprintf(tmp, SHOL_IO_PATH_MAX, "%s/.%s.tmp.%ld", dir, name, (long)getpid());
    if (n1 < 0 || n2 < 0 || n1 >= SHOL_IO_PATH_MAX || n2 >= SHOL_IO_PATH_MAX)
        return core_err_set(err, -1, "%s/%s: path too long", dir, name);
    return 0;
}

FILE *shol_io_open(const char *tmp, core_err *err)
{
    FILE *f = fopen(tmp, "w");
    if (!f)
        core_err_set(err, -1, "%s: cannot write: %s", tmp, strerror(errno));
    return f;
}

void shol_io_abort(FILE *f, const char *tmp)
{
    if (f)
        fclose(f);
    unlink(tmp);
}

int shol_io_commit(FILE *f, const char *tmp, const char *final, core_err *err)
{
    if (f) {
        /* Keep the first failure's errno; fsync makes the rename publish
         * data that is on disk (EINVAL: a file system without fsync). */
        int saved = 0;
        if (ferror(f))
            saved = EIO;
        if (fflush(f) != 0 && !saved)
            saved = errno;
        if (fsync(fileno(f)) != 0 && errno != EINVAL && !saved)
            saved = errno;
        if (fclose(f) != 0 && !saved)
            saved = errno;
        if (saved) {
            unlink(tmp);
            return core_err_set(err, -1, "%s: write failed: %s", final, strerror(saved));
        }
    } else {
        /* Written by cairo: flush it to disk before it gets its name. */
        int fd = open(tmp, O_RDONLY);
        if (fd < 0) {
            int saved = errno;
            unlink(tmp);
            return core_err_set(err, -1, "%s: cannot reopen: %s", tmp, strerror(saved));
        }
        fsync(fd);
        close(fd);
    }
    if (rename(tmp, final) < 0) {
        int saved = errno;
        unlink(tmp);
        return core_err_set(err, -1, "%s: cannot rename into place: %s", final, strerror(saved));
    }
    return 0;
}

void shol_io_num(FILE *f, const char *fmt, double v)
{
    if (isfinite(v))
        fprintf(f, fmt, v);
    else
        fputs("nan", f);
}

void shol_io_band_csv(FILE *f, const shol_band *b, const char *fmt)
{
    const double bv[5] = {b->lo_mps, b->hi_mps, b->grid_mps, b->window_mps, b->sens_mps};
    for (int k = 0; k < 5; k++) {
        fputc(',', f);
        shol_io_num(f, fmt, bv[k] / CORE_KMH_TO_MPS);
    }
    fprintf(f, ",%d,%d,", b->open_above, b->low_confidence);
    shol_io_num(f, fmt, b->model_mps / CORE_KMH_TO_MPS);
}

void shol_io_band_json(FILE *f, const shol_band *b, const char *fmt)
{
    static const char *const key[6] = {"lo_kmh", "hi_kmh", "grid_kmh", "window_kmh", "sens_kmh", "model_kmh"};
    const double bv[6] = {b->lo_mps, b->hi_mps, b->grid_mps, b->window_mps, b->sens_mps, b->model_mps};
    for (int k = 0; k < 6; k++) {
        fprintf(f, "%s\"%s\": ", k ? ", " : "{", key[k]);
        if (isfinite(bv[k]))
            fprintf(f, fmt, bv[k] / CORE_KMH_TO_MPS);
        else
            fputs("null", f);
    }
    /* the model's error behind model_kmh: its quantity, value (deg or % of
     * travel) and reference; null where not validated */
    fprintf(f, ", \"model_quantity\": ");
    if (b->model_crit >= 0 && b->model_crit < SHOL_NCRIT)
        fprintf(f, "\"%s\"", shol_limit_name(b->model_crit));
    else
        fputs("null", f);
    fputs(", \"model_error\": ", f);
    if (isfinite(b->model_err) && b->model_crit >= 0)
        fprintf(f, fmt, b->model_err * (b->model_crit <= SHOL_CRIT_PITCH ? CORE_RAD_TO_DEG : 1.0));
    else
        fputs("null", f);
    fputs(", \"model_reference\": \"", f);
    for (const char *c = b->model_ref; *c; c++)
        if ((unsigned char)*c >= 0x20 && *c != '"' && *c != '\\')
            fputc(*c, f);
    fprintf(f, "\", \"open_above\": %s, \"widest\": \"%s\", \"low_confidence\": %s}", b->open_above ? "true" : "false",
            shol_band_source_name(b->widest), b->low_confidence ? "true" : "false");
}

/* Length of the well-formed UTF-8 sequence at s (RFC 3629: no overlong
 * forms, no surrogates, at most U+10FFFF), or 0. */
static int utf8_len(const unsigned char *s)
{
    if (s[0] < 0x80)
        return 1;
    int n = s[0] >= 0xc2 && s[0] <= 0xdf ? 2 : s[0] >= 0xe0 && s[0] <= 0xef ? 3 : s[0] >= 0xf0 && s[0] <= 0xf4 ? 4 : 0;
    for (int i = 1; i < n; i++)
        if ((s[i] & 0xc0) != 0x80)
            return 0;
    if ((s[0] == 0xe0 && s[1] < 0xa0) || (s[0] == 0xed && s[1] > 0x9f) || (s[0] == 0xf0 && s[1] < 0x90) ||
        (s[0] == 0xf4 && s[1] > 0x8f))
        return 0;
    return n;
}

/* JSON string with the escapes JSON needs. JSON text is UTF-8 (RFC 8259
 * section 8.1): a byte that is not part of a well-formed sequence (a path
 * in Latin-1) becomes U+FFFD, so that a JSON reader takes the file. */
void shol_io_json_str(FILE *f, const char *s)
{
    fputc('"', f);
    for (; s && *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c >= 0x80) {
            int n = utf8_len((const unsigned char *)s);
            if (n == 0)
                fputs("\\ufffd", f);
            else
                fwrite(s, 1, (size_t)n, f);
            s += n > 0 ? n - 1 : 0;
            continue;
        }
        if (c == '"' || c == '\\')
            fprintf(f, "\\%c", c);
        else if (c == '\n')
            fputs("\\n", f);
        else if (c < 0x20)
            fprintf(f, "\\u%04x", c);
        else
            fputc(c, f);
    }
    fputc('"', f);
}

void shol_io_json_num(FILE *f, const char *fmt, double v)
{
    if (isfinite(v))
        fprintf(f, fmt, v);
    else
        fputs("null", f);
}
