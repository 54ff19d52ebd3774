/* launch.c -- starting the background airwake builder for a client
 * (disim shol) when none serves its database. The library that waits for
 * fields (awdb_fields) knows no executable or flag; it calls this. */
#include "cmds.h"

#include <fcntl.h>
#include <libgen.h>
#include <stdio.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

int app_launcher_init(app_launcher *l, const sim_scenario *sc, int max_iter)
{
    memset(l, 0, sizeof *l);
    l->max_iter = max_iter;
    l->foam_np = sc->engine == SIM_ENGINE_OPENFOAM ? (sc->engine_np > 0 ? sc->engine_np : 2) : 0;
    char tmp[sizeof l->ships_dir];
    snprintf(tmp, sizeof tmp, "%s", sc->ship_path);
    snprintf(l->ships_dir, sizeof l->ships_dir, "%s", dirname(tmp));
    snprintf(tmp, sizeof tmp, "%s", sc->aircraft_path);
    snprintf(l->aircraft_dir, sizeof l->aircraft_dir, "%s", dirname(tmp));
    ssize_t n = readlink("/proc/self/exe", l->exe, sizeof l->exe - 1);
    if (n <= 0) {
        l->exe[0] = '\0';
        return -1;
    }
    l->exe[n] = '\0';
    return 0;
}

const char *app_db_default(const sim_scenario *sc)
{
    return sc->engine == SIM_ENGINE_OPENFOAM ? "out/airwake-db-openfoam" : "out/airwake-db";
}

int app_launch_builder(void *user, const char *db_dir)
{
    app_launcher *l = user;
    if (!l->exe[0])
        return -1;
    if (l->pid > 0 && waitpid((pid_t)l->pid, NULL, WNOHANG) == 0)
        return 0; /* ours is still starting up */
    pid_t pid = fork();
    if (pid < 0)
        return -1;
    if (pid == 0) {
        char logp[1100];
        snprintf(logp, sizeof logp, "%s/builder.log", db_dir);
        int fd = open(logp, O_WRONLY | O_CREAT | O_APPEND, 0666);
        if (fd >= 0) {
            dup2(fd, 1);
            dup2(fd, 2);
            close(fd);
        }
        setsid(); /* outlives this process if another client still waits */
        char it[32], np[32];
        snprintf(it, sizeof it, "%d", l->max_iter);
        snprintf(np, sizeof np, "%d", l->foam_np);
        char *argv[20];
        int a = 0;
        argv[a++] = l->exe;
        argv[a++] = "airwaked";
        argv[a++] = (char *)db_dir;
        argv[a++] = "--exit-when-idle";
        argv[a++] = "--ships";
        argv[a++] = l->ships_dir;
        argv[a++] = "--no-lcm";
        if (l->max_iter > 0) {
            argv[a++] = "--max-iter";
            argv[a++] = it;
        }
        if (l->foam_np > 0) {
            argv[a++] = "--engine";
            argv[a++] = "openfoam";
            argv[a++] = "--np";
            argv[a++] = np;
            argv[a++] = "--aircraft";
            argv[a++] = l->aircraft_dir;
        }
        argv[a] = NULL;
        execv(l->exe, argv);
        _exit(127);
    }
    l->pid = (long)pid;
    fprintf(stderr, "shol: started an airwake builder (pid %ld), its log in %s/builder.log\n", (long)pid, db_dir);
    return 0;
}
