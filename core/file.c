/* file.c -- what a reader accepts as an input file: a regular file of at most
 * a given size. A folder, a FIFO, a device (/dev/zero) or a socket would
 * block, never end, or read as garbage; each is refused with a message that
 * says what the path is. An output is written to a temporary and renamed
 * over its target: a target that is a device or a FIFO would be replaced by
 * a regular file, and one that is an input of the same run overwritten, so
 * both are refused before any work. */
#include "core.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static const char *kind_of(mode_t m)
{
    if (S_ISDIR(m))
        return "a folder";
    if (S_ISFIFO(m))
        return "a FIFO";
    if (S_ISCHR(m))
        return "a character device";
    if (S_ISBLK(m))
        return "a block device";
    if (S_ISSOCK(m))
        return "a socket";
    return "not a regular file";
}

int core_file_check_stat(const char *path, const struct stat *st, long long max_bytes, core_err *err)
{
    if (!S_ISREG(st->st_mode))
        return core_err_set(err, -1, "%s: %s, expected a regular file", path, kind_of(st->st_mode));
    if (max_bytes >= 0 && (long long)st->st_size > max_bytes)
        return core_err_set(err, -1, "%s: %lld bytes, larger than the %lld bytes a file of this kind may have",
                            path, (long long)st->st_size, max_bytes);
    return 0;
}

int core_file_regular(const char *path, long long max_bytes, core_err *err)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return core_err_set(err, -1, "%s: cannot open: %s", path, strerror(errno));
    return core_file_check_stat(path, &st, max_bytes, err);
}

char *core_file_read(const char *path, long long max, size_t *len, core_err *err)
{
    /* O_NONBLOCK: a FIFO opens at once (and is then refused) */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        core_err_set(err, -1, "%s: cannot open: %s", path, strerror(errno));
        return NULL;
    }
    struct stat st;
    if (fstat(fd, &st) != 0) {
        core_err_set(err, -1, "%s: cannot read: %s", path, strerror(errno));
        close(fd);
        return NULL;
    }
    if (core_file_check_stat(path, &st, max, err)) {
        close(fd);
        return NULL;
    }
    /* the size read, not the size stat gave: a file that grows meanwhile
     * is read up to max and refused past it */
    size_t limit = max < 0 || (unsigned long long)max >= SIZE_MAX / 2 ? SIZE_MAX / 2 : (size_t)max;
    size_t cap = (size_t)st.st_size + 1, n = 0;
    char *buf = malloc(cap + 1);
    if (!buf)
        goto oom;
    for (;;) {
        if (n == cap) {
            if (n > limit) {
                core_err_set(err, -1, "%s: larger than the %lld bytes a file of this kind may have", path, max);
                goto fail;
            }
            size_t ncap = cap > limit / 2 ? limit + 1 : 2 * cap;
            char *nb = realloc(buf, ncap + 1);
            if (!nb)
                goto oom;
            buf = nb;
            cap = ncap;
        }
        ssize_t r = read(fd, buf + n, cap - n);
        if (r < 0 && errno == EINTR)
            continue;
        if (r < 0) {
            /* what was read is only the start of the file: a reader would
             * take it for the whole */
            core_err_set(err, -1, "%s: cannot read: %s", path, strerror(errno));
            goto fail;
        }
        if (r == 0)
            break;
        n += (size_t)r;
    }
    close(fd);
    buf[n] = '\0';
    *len = n;
    return buf;
oom:
    core_err_set(err, -1, "%s: out of memory", path);
fail:
    free(buf);
    close(fd);
    return NULL;
}

int core_output_check(const char *path, core_err *err)
{
    struct stat st;
    if (!path || !*path)
        return core_err_set(err, -1, "an output needs a file name");
    if (lstat(path, &st) != 0) {
        if (errno == ENOENT)
            return 0;
        return core_err_set(err, -1, "%s: cannot write: %s", path, strerror(errno));
    }
    if (S_ISLNK(st.st_mode) && stat(path, &st) != 0)
        return 0; /* a dangling link: the rename replaces the link */
    if (!S_ISREG(st.st_mode))
        return core_err_set(err, -1, "%s: %s: expected a regular file or a new name for an output "
                            "(it is written whole and renamed over its target)", path, kind_of(st.st_mode));
    return 0;
}

/* The folder of path made absolute (realpath) with the last part added:
 * the same for two spellings of a file that does not exist yet. */
static int canonical(const char *path, char *out, size_t n)
{
    char dir[PATH_MAX], real[PATH_MAX];
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    if (slash) {
        size_t len = slash == path ? 1 : (size_t)(slash - path);
        if (len >= sizeof dir)
            return -1;
        memcpy(dir, path, len);
        dir[len] = '\0';
    } else {
        snprintf(dir, sizeof dir, ".");
    }
    if (!realpath(dir, real))
        return -1;
    int w = snprintf(out, n, "%s/%s", real, base);
    return w < 0 || (size_t)w >= n ? -1 : 0;
}

int core_path_same(const char *a, const char *b)
{
    if (!a || !b)
        return 0;
    if (!strcmp(a, b))
        return 1;
    struct stat sa, sb;
    int ea = stat(a, &sa) == 0, eb = stat(b, &sb) == 0;
    if (ea && eb)
        return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    if (ea != eb)
        return 0;
    char ca[PATH_MAX + 256], cb[PATH_MAX + 256];
    return canonical(a, ca, sizeof ca) == 0 && canonical(b, cb, sizeof cb) == 0 && !strcmp(ca, cb);
}
