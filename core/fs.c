/* fs.c -- folders: create a path with its parents (mkdir -p), in C rather
 * than through a shell, so that any file name (quotes, spaces) works; and
 * fsync by path (files written by another library, folders after a rename). */
#include "core.h"

#include <errno.h>
#include <stdio.h>
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

int core_dir_check(const char *dir, core_err *err)
{
    if (!dir || !*dir)
        return core_err_set(err, -1, "empty folder name");
    char p[4096];
    if (strlen(dir) >= sizeof p - 64)
        return core_err_set(err, -1, "%s: folder name too long", dir);
    /* the folder, or the nearest part of it that exists, must be a folder
     * that can be written */
    snprintf(p, sizeof p, "%s", dir);
    for (;;) {
        struct stat st;
        if (stat(p, &st) == 0) {
            const char *of = strcmp(p, dir) ? " (on the way to the folder " : "", *end = *of ? ")" : "";
            if (!S_ISDIR(st.st_mode))
                return core_err_set(err, -1, "%s: not a folder%s%s%s", p, of, *of ? dir : "", end);
            if (access(p, W_OK | X_OK) != 0)
                return core_err_set(err, -1, "%s: cannot write in it: %s%s%s%s", p, strerror(errno), of,
                                    *of ? dir : "", end);
            return 0;
        }
        if ((errno != ENOENT && errno != ENOTDIR) || !strcmp(p, "."))
            return core_err_set(err, -1, "%s: %s", p, strerror(errno));
        char *slash = strrchr(p, '/');
        while (slash && slash > p && slash[1] == '\0') { /* trailing slashes */
            *slash = '\0';
            slash = strrchr(p, '/');
        }
        if (!slash) {
            snprintf(p, sizeof p, ".");
            continue;
        }
        if (slash == p)
            p[1] = '\0';
        else
            *slash = '\0';
    }
}
