/* fs.c -- folders: create a path with its parents (mkdir -p), in C rather
 * than through a shell, so that any file name (quotes, spaces) works; and
 * fsync by path (files written by another library, folders after a rename). */
#include "core.h"

#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int core_sync_path(const char *path)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return -1;
    int rc = fsync(fd);
    int e = errno;
    close(fd);
    errno = e;
    return rc;
}

int core_mkdir_p(const char *dir, core_err *err)
{
    char p[4096];
    if (!dir || !*dir)
        return core_err_set(err, -1, "empty folder name");
    if (strlen(dir) >= sizeof p)
        return core_err_set(err, -1, "%.64s...: folder name too long", dir);
    strcpy(p, dir);
    for (char *c = p + 1;; c++) {
        int end = *c == '\0';
        if (*c == '/' || end) {
            char keep = *c;
            *c = '\0';
            if (mkdir(p, 0777) < 0 && errno != EEXIST)
                return core_err_set(err, -1, "%s: cannot create folder: %s", p, strerror(errno));
            *c = keep;
        }
        if (end)
            break;
    }
    struct stat st;
    if (stat(dir, &st) < 0 || !S_ISDIR(st.st_mode))
        return core_err_set(err, -1, "%s: not a folder", dir);
    return 0;
}
