/* run.c -- OpenFOAM's programs as child processes: fork and execve (no
 * shell; the program found on PATH and the environment built before the
 * fork, so the child only calls async-signal-safe functions, as a
 * multi-threaded builder needs), each in its own process group so that a
 * time limit or a stop ends mpirun and its ranks together, its output in a
 * log file of the case. */
#include "foam_private.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

extern char **environ;

int foam_which(const char *prog, char *out, size_t n)
{
    if (strchr(prog, '/')) {
        snprintf(out, n, "%s", prog);
        return access(prog, X_OK) == 0;
    }
    const char *path = getenv("PATH");
    if (!path || !*path)
        path = "/usr/local/bin:/usr/bin:/bin";
    while (*path) {
        const char *e = strchr(path, ':');
        size_t len = e ? (size_t)(e - path) : strlen(path);
        if (len > 0 && (size_t)snprintf(out, n, "%.*s/%s", (int)len, path, prog) < n && access(out, X_OK) == 0) {
            struct stat st;
            if (stat(out, &st) == 0 && S_ISREG(st.st_mode))
                return 1;
        }
        path += len + (e ? 1 : 0);
    }
    return 0;
}

void foam_log_tail(const char *path, char *buf, size_t n)
{
    buf[0] = '\0';
    FILE *f = fopen(path, "rb");
    if (!f || n < 2) {
        if (f)
            fclose(f);
        return;
    }
    long want = (long)n - 1;
    if (fseek(f, 0, SEEK_END) == 0) {
        long size = ftell(f);
        fseek(f, size > want ? size - want : 0, SEEK_SET);
    }
    size_t got = fread(buf, 1, n - 1, f);
    fclose(f);
    buf[got] = '\0';
    /* from the first whole line, without the trailing newlines */
    char *nl = got == n - 1 ? strchr(buf, '\n') : NULL;
    if (nl)
        memmove(buf, nl + 1, strlen(nl + 1) + 1);
    size_t l = strlen(buf);
    while (l > 0 && (buf[l - 1] == '\n' || buf[l - 1] == ' '))
        buf[--l] = '\0';
}

/* A log's tail for an error message: its lines joined with " | ", blank
 * lines and MPI's rules of dashes left out (an error message is one line:
 * core_err_set escapes a newline). */
static void tidy_tail(const char *in, char *out, size_t size)
{
    size_t w = 0;
    out[0] = '\0';
    for (const char *l = in; *l;) {
        size_t n = strcspn(l, "\n");
        size_t lead = strspn(l, " \t");
        int rule = n > 0 && strspn(l, "-") == n;
        if (n > lead && !rule) {
            int k = snprintf(out + w, size - w, "%s%.*s", w ? " | " : "", (int)(n - lead), l + lead);
            if (k < 0 || (size_t)k >= size - w)
                break;
            w += (size_t)k;
        }
        l += n + (l[n] == '\n');
    }
}

/* environ with FOAM_ETC and WM_PROJECT_DIR set (etc's parent), and
 * OpenMPI's shared-memory transport told not to use cross-memory attach
 * (refused in containers without ptrace rights). NULL out of memory. */
static char **child_env(const char *etc, const char *case_dir)
{
    size_t n = 0;
    while (environ[n])
        n++;
    char **env = calloc(n + 5, sizeof *env);
    if (!env)
        return NULL;
    size_t m = 0;
    for (size_t i = 0; i < n; i++)
        if (strncmp(environ[i], "FOAM_ETC=", 9) && strncmp(environ[i], "WM_PROJECT_DIR=", 15) &&
            strncmp(environ[i], "OMPI_MCA_btl_vader_single_copy_mechanism=", 41) && strncmp(environ[i], "PWD=", 4))
            env[m++] = environ[i];
    size_t le = strlen(etc);
    char *a = malloc(le + 16), *b = malloc(le + 24), *c = strdup("OMPI_MCA_btl_vader_single_copy_mechanism=none");
    char *d = malloc(strlen(case_dir) + 8);
    if (!a || !b || !c || !d) {
        free(a), free(b), free(c), free(d), free(env);
        return NULL;
    }
    /* the child starts in the case folder; OpenFOAM checks PWD against it */
    snprintf(d, strlen(case_dir) + 8, "PWD=%s", case_dir);
    snprintf(a, le + 16, "FOAM_ETC=%s", etc);
    const char *slash = strrchr(etc, '/');
    size_t lp = slash && slash != etc ? (size_t)(slash - etc) : le;
    snprintf(b, le + 24, "WM_PROJECT_DIR=%.*s", (int)lp, etc);
    env[m++] = a;
    env[m++] = b;
    env[m++] = c;
    env[m++] = d;
    env[m] = NULL;
    return env;
}

static void free_env(char **env)
{
    if (!env)
        return;
    size_t m = 0;
    while (env[m])
        m++;
    /* the last four are ours */
    for (size_t i = m >= 4 ? m - 4 : 0; i < m; i++)
        free(env[i]);
    free(env);
}

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

/* End the child's process group: TERM, then KILL after 5 s. */
static void end_group(pid_t pid, int *status)
{
    kill(-pid, SIGTERM);
    for (int i = 0; i < 50; i++) {
        if (waitpid(pid, status, WNOHANG) == pid) {
            kill(-pid, SIGKILL); /* ranks left behind */
            return;
        }
        nanosleep(&(struct timespec){0, 100000000}, NULL);
    }
    kill(-pid, SIGKILL);
    waitpid(pid, status, 0);
}

int foam_exec(const char *case_dir, const char *step, char *const argv[], const char *etc, double timeout_s,
              foam_poll_fn poll, void *poll_user, core_err *err)
{
    char prog[1024], logp[1200], tail[600];
    snprintf(logp, sizeof logp, "%s/log.%s", case_dir, step);
    if (!foam_which(argv[0], prog, sizeof prog))
        return core_err_set(err, -1, "OpenFOAM step %s: %s not found on PATH", step, argv[0]);
    int logfd = open(logp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    int nullfd = open("/dev/null", O_RDONLY | O_CLOEXEC);
    char **env = child_env(etc, case_dir);
    if (logfd < 0 || nullfd < 0 || !env) {
        int e = errno;
        if (logfd >= 0)
            close(logfd);
        if (nullfd >= 0)
            close(nullfd);
        free_env(env);
        return core_err_set(err, -1, "OpenFOAM step %s: cannot start: %s", step, env ? strerror(e) : "out of memory");
    }
    pid_t pid = fork();
    if (pid == 0) {
        setpgid(0, 0);
        if (chdir(case_dir) != 0 || dup2(nullfd, 0) < 0 || dup2(logfd, 1) < 0 || dup2(logfd, 2) < 0)
            _exit(126);
        execve(prog, argv, env);
        _exit(127);
    }
    int fe = errno;
    close(logfd);
    close(nullfd);
    free_env(env);
    if (pid < 0)
        return core_err_set(err, -1, "OpenFOAM step %s: fork: %s", step, strerror(fe));
    setpgid(pid, pid); /* also here: no race with an early stop */
    double t0 = now_s(), last_poll = t0;
    int status = 0, stopped = 0, timed_out = 0;
    for (;;) {
        pid_t w = waitpid(pid, &status, WNOHANG);
        if (w == pid)
            break;
        if (w < 0 && errno != EINTR) {
            status = -1;
            break;
        }
        double t = now_s();
        if (timeout_s > 0.0 && t - t0 > timeout_s) {
            timed_out = 1;
            end_group(pid, &status);
            break;
        }
        if (poll && t - last_poll >= 1.0) {
            last_poll = t;
            if (poll(poll_user)) {
                stopped = 1;
                end_group(pid, &status);
                break;
            }
        }
        nanosleep(&(struct timespec){0, 50000000}, NULL);
    }
    if (stopped)
        return 1;
    if (!timed_out && status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 0)
        return 0;
    char raw[sizeof tail];
    foam_log_tail(logp, raw, sizeof raw);
    tidy_tail(raw, tail, sizeof tail);
    if (timed_out)
        return core_err_set(err, -1, "OpenFOAM step %s: no result after %.0f s (the time limit); the end of %s: %s",
                            step, timeout_s, logp, tail);
    if (status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 127)
        return core_err_set(err, -1, "OpenFOAM step %s: %s could not be started", step, prog);
    if (status != -1 && WIFSIGNALED(status))
        return core_err_set(err, -1, "OpenFOAM step %s: killed by signal %d; the end of %s: %s", step,
                            WTERMSIG(status), logp, tail);
    return core_err_set(err, -1, "OpenFOAM step %s failed (exit %d); the end of %s: %s", step,
                        status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1, logp, tail);
}
