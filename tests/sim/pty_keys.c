/* pty_keys.c -- run a command on a pseudo-terminal and type at it, for
 * station_cli.sh (the keyboard of `disim station`).
 *
 *   pty_keys WAIT_S GAP_S "KEYS" CMD [ARGS...]
 *
 * starts CMD with the slave side of a new pty as its controlling terminal
 * (stdin, stdout, stderr), waits WAIT_S, then sends the keys, GAP_S apart,
 * each in one write: a word of KEYS separated by spaces is up, down, left,
 * right (ESC [ A..D), space, ctrl-c (byte 3: SIGINT through the terminal),
 * or TERM / ABRT (no byte: that signal to CMD), else its characters. What
 * CMD writes goes to standard output. After CMD ends (or 20 s, then it is
 * killed) the terminal's settings are compared with those before it
 * started: "pty_keys: terminal restored" or "pty_keys: terminal NOT
 * restored" and exit 3. Otherwise the exit status is CMD's, 128 + the
 * signal if a signal ended it. */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/wait.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void drain(int master)
{
    char buf[4096];
    for (;;) {
        ssize_t n = read(master, buf, sizeof buf);
        if (n <= 0)
            return;
        fwrite(buf, 1, (size_t)n, stdout);
    }
}

int main(int argc, char **argv)
{
    if (argc < 5) {
        fprintf(stderr, "usage: pty_keys WAIT_S GAP_S \"KEYS\" CMD [ARGS...]\n");
        return 2;
    }
    double wait_s = atof(argv[1]), gap_s = atof(argv[2]);
    char *keys = strdup(argv[3]);
    char *tok[256];
    int ntok = 0;
    for (char *t = strtok(keys, " "); t && ntok < 256; t = strtok(NULL, " "))
        tok[ntok++] = t;
    int master, slave;
    struct winsize ws = {24, 132, 0, 0};
    if (openpty(&master, &slave, NULL, NULL, &ws) != 0) {
        perror("openpty");
        return 2;
    }
    struct termios before, after;
    if (tcgetattr(slave, &before) != 0) {
        perror("tcgetattr");
        return 2;
    }
    pid_t pid = fork();
    if (pid < 0) {
        perror("fork");
        return 2;
    }
    if (pid == 0) {
        close(master);
        setsid();
        if (ioctl(slave, TIOCSCTTY, 0) != 0)
            perror("TIOCSCTTY");
        dup2(slave, 0);
        dup2(slave, 1);
        dup2(slave, 2);
        if (slave > 2)
            close(slave);
        execvp(argv[4], argv + 4);
        perror(argv[4]);
        _exit(127);
    }
    fcntl(master, F_SETFL, fcntl(master, F_GETFL) | O_NONBLOCK);
    double t0 = now_s(), next = t0 + wait_s;
    int k = 0, status = 0, done = 0;
    while (!done) {
        double t = now_s();
        if (k < ntok && t >= next) {
            const char *w = tok[k++];
            const char *bytes = w;
            int sig = 0;
            if (!strcmp(w, "up"))
                bytes = "\033[A";
            else if (!strcmp(w, "down"))
                bytes = "\033[B";
            else if (!strcmp(w, "right"))
                bytes = "\033[C";
            else if (!strcmp(w, "left"))
                bytes = "\033[D";
            else if (!strcmp(w, "space"))
                bytes = " ";
            else if (!strcmp(w, "ctrl-c"))
                bytes = "\003";
            else if (!strcmp(w, "TERM"))
                sig = SIGTERM;
            else if (!strcmp(w, "ABRT"))
                sig = SIGABRT;
            if (sig)
                kill(pid, sig);
            else if (write(master, bytes, strlen(bytes)) != (ssize_t)strlen(bytes))
                perror("write");
            next += gap_s;
        }
        struct pollfd pf = {master, POLLIN, 0};
        poll(&pf, 1, 10);
        drain(master);
        pid_t r = waitpid(pid, &status, WNOHANG);
        if (r == pid)
            done = 1;
        else if (t - t0 > 20.0) {
            fprintf(stderr, "pty_keys: %s still running after 20 s: killed\n", argv[4]);
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            done = 1;
        }
    }
    drain(master);
    fflush(stdout);
    if (k < ntok)
        fprintf(stderr, "pty_keys: %s ended before %d of the %d keys were sent\n", argv[4], ntok - k, ntok);
    if (tcgetattr(slave, &after) != 0) {
        perror("tcgetattr after");
        return 2;
    }
    int same = before.c_lflag == after.c_lflag && before.c_iflag == after.c_iflag &&
               before.c_oflag == after.c_oflag && before.c_cc[VMIN] == after.c_cc[VMIN] &&
               before.c_cc[VTIME] == after.c_cc[VTIME];
    fprintf(stderr, "pty_keys: terminal %s (lflag %#lx, was %#lx)\n", same ? "restored" : "NOT restored",
            (unsigned long)after.c_lflag, (unsigned long)before.c_lflag);
    if (!same)
        return 3;
    if (WIFSIGNALED(status))
        return 128 + WTERMSIG(status);
    return WEXITSTATUS(status);
}
