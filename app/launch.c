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

int app_launcher_init(app_launcher *l, const char *ship_path, int max_iter)
{
    memset(l, 0, sizeof *l);
    l->max_iter = max_iter;
    char ships[sizeof l->ships_dir];
    snprintf(ships, sizeof ships, "%s", ship_path);
    snprintf(l->ships_dir, sizeof l->ships_dir, "%s", dirname(ships));
    ssize_t n = readlink("/proc/self/exe", l->exe, sizeof l->exe - 1);
    if (n <= 0) {
        l->exe[0] = '\0';
        return -1;
    }
    l->exe[n] = '\0';
    return 0;
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
        char it[32];
        snprintf(it, sizeof it, "%d", l->max_iter);
        if (l->max_iter > 0)
            execl(l->exe, l->exe, "airwaked", db_dir, "--exit-when-idle", "--ships", l->ships_dir, "--no-lcm",
                  "--max-iter", it, (char *)NULL);
        else
            execl(l->exe, l->exe, "airwaked", db_dir, "--exit-when-idle", "--ships", l->ships_dir, "--no-lcm",
                  (char *)NULL);
        _exit(127);
    }
    l->pid = (long)pid;
    fprintf(stderr, "shol: started an airwake builder (pid %ld), its log in %s/builder.log\n", (long)pid, db_dir);
    return 0;
}
