/* engine_mark.c -- which engine a database's fields come from.
 *
 * A key does not name its engine, so a database holds one engine's
 * fields: DB/engine is one line with the engine's name ("embedded",
 * "openfoam"). The first builder or client that opens the database for an
 * engine writes it (to a temporary name, then link(): of two at once one
 * wins, and the other reads what it wrote); every later one checks it. A
 * database that has fields but no engine file was written before the file
 * existed, by the embedded engine. */
#include "awdb_private.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#define ENGINE_NAME_MAX 32

/* The engine file's name into name: 0; 1 when there is no file; < 0 with
 * err when it cannot be read or is not an engine's name. */
static int read_mark(const char *path, char *name, core_err *err)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return errno == ENOENT ? 1 : core_err_set(err, -1, "%s: %s", path, strerror(errno));
    char line[ENGINE_NAME_MAX + 8] = "";
    int ok = fgets(line, sizeof line, f) != NULL;
    fclose(f);
    size_t n = ok ? strcspn(line, "\n") : 0;
    int good = n > 0 && n < ENGINE_NAME_MAX && line[n] == '\n';
    for (size_t i = 0; good && i < n; i++)
        good = line[i] >= 'a' && line[i] <= 'z';
    if (!good)
        return core_err_set(err, -1, "%s: expected one line naming the engine of the database's fields "
                                     "(embedded or openfoam)",
                            path);
    line[n] = '\0';
    memcpy(name, line, n + 1);
    return 0;
}

/* 1 when DB/fields has a field file. */
static int has_fields(const awdb *db)
{
    char p[AWDB_PATH];
    awdb_fmt(p, sizeof p, "%s/fields", db->dir);
    DIR *d = opendir(p);
    if (!d)
        return 0;
    struct dirent *e;
    int any = 0;
    while (!any && (e = readdir(d))) {
        size_t l = strlen(e->d_name);
        any = l > 3 && !strcmp(e->d_name + l - 3, ".h5");
    }
    closedir(d);
    return any;
}

/* Write name as the engine file unless one is there: 0 written or already
 * there, < 0 with err. */
static int write_mark(const awdb *db, const char *path, const char *name, core_err *err)
{
    char tmp[AWDB_PATH];
    awdb_fmt(tmp, sizeof tmp, "%s/.tmp-engine.%ld", db->dir, (long)getpid());
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC, 0666);
    if (fd < 0)
        return core_err_set(err, -1, "%s: %s", tmp, strerror(errno));
    char line[ENGINE_NAME_MAX + 2];
    int len = snprintf(line, sizeof line, "%s\n", name);
    int bad = write(fd, line, (size_t)len) != len || fsync(fd) != 0;
    bad |= close(fd) != 0;
    int rc = 0;
    if (bad)
        rc = core_err_set(err, -1, "%s: cannot write: %s", tmp, strerror(errno));
    else if (link(tmp, path) != 0 && errno != EEXIST)
        rc = core_err_set(err, -1, "%s: %s", path, strerror(errno));
    unlink(tmp);
    return rc;
}

int awdb_engine_claim(awdb *db, const char *engine, core_err *err)
{
    size_t n = strlen(engine);
    if (n == 0 || n >= ENGINE_NAME_MAX || strspn(engine, "abcdefghijklmnopqrstuvwxyz") != n)
        return core_err_set(err, -1, "engine '%s': expected a lower-case name", engine);
    char path[AWDB_PATH], have[ENGINE_NAME_MAX];
    awdb_fmt(path, sizeof path, "%s/engine", db->dir);
    int rc = read_mark(path, have, err);
    if (rc == 1) {
        /* no engine file: the database's first opener, or fields from before it */
        if ((rc = write_mark(db, path, has_fields(db) ? "embedded" : engine, err)) != 0)
            return rc;
        rc = read_mark(path, have, err);
    }
    if (rc != 0)
        return rc < 0 ? rc : core_err_set(err, -1, "%s: missing after it was written", path);
    if (strcmp(have, engine) != 0)
        return core_err_set(err, -1,
                            "%s holds the %s engine's fields (%s); this asks for the %s engine's: give it a "
                            "database folder of its own",
                            db->dir, have, path, engine);
    return 0;
}
