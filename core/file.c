/* file.c -- what a reader accepts as an input file: a regular file of at most
 * a given size. A folder, a FIFO, a device (/dev/zero) or a socket would
 * block, never end, or read as garbage; each is refused with a message that
 * says what the path is. */
#include "core.h"

#include <errno.h>
#include <string.h>
#include <sys/stat.h>

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
