/* cmd_ios.c -- `disim ios`: the instructor's console. Commands typed at
 * the terminal (or given by --cmd, or read from --script) go to the
 * flight loop as sim_control_t; each answer, from its sim_status_t, is
 * printed. This file parses the flags and reads the lines; the console
 * itself is sim/ios.c. */
#include "cmds.h"
#include "sim.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define IOS_CMDS_MAX 64

static void usage_ios(FILE *f)
{
    fprintf(f,
            "usage: disim ios [--lcm URL] [--timeout-s S] [--cmd \"COMMAND\"]... [--script FILE]\n"
            "  the instructor's console of a running disim fly: each command is sent as a\n"
            "  sim_control_t on DISIM_SIM_CONTROL and its answer (accepted, or refused and why)\n"
            "  read from the loop's sim_status_t within --timeout-s (10). Without --cmd or\n"
            "  --script the commands are read from standard input, one a line. --cmd (repeated)\n"
            "  runs its commands in order, then --script's lines ('#' starts a comment).\n"
            "  Exit status: 0 every command accepted; 1 one refused, not answered, or not a\n"
            "  command (not answered and not a command stop the run); 2 usage.\n"
            "commands:\n%s",
            sim_ios_help());
}

typedef struct ios_args {
    const char *url, *script;
    const char *cmd[IOS_CMDS_MAX];
    int ncmd;
    double timeout_s;
} ios_args;

/* The flags into o: -1 to go on, else the exit status. */
static int ios_parse_args(int argc, char **argv, ios_args *o)
{
    static const char P[] = "ios";
    memset(o, 0, sizeof *o);
    o->timeout_s = 10.0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage_ios(stdout);
            return 0;
        }
        int known = !strcmp(a, "--lcm") || !strcmp(a, "--script") || !strcmp(a, "--cmd") || !strcmp(a, "--timeout-s");
        if (!known) {
            fprintf(stderr, "%s: unknown argument '%s'\n", P, a);
            usage_ios(stderr);
            return 2;
        }
        if (!v) {
            fprintf(stderr, "%s: %s: expected a value after it\n", P, a);
            return 2;
        }
        i++;
        if (!strcmp(a, "--lcm"))
            o->url = v;
        else if (!strcmp(a, "--script"))
            o->script = v;
        else if (!strcmp(a, "--timeout-s")) {
            if (app_parse_double(P, a, v, 0.1, 3600.0, &o->timeout_s) != 0)
                return 2;
        } else if (o->ncmd == IOS_CMDS_MAX) {
            fprintf(stderr, "%s: --cmd: at most %d\n", P, IOS_CMDS_MAX);
            return 2;
        } else
            o->cmd[o->ncmd++] = v;
    }
    return -1;
}

/* One line: 0 done (accepted, or nothing to send), 1 refused, -1 stop
 * (not answered, not a command), 2 quit. */
static int ios_line(sim_ios *io, const ios_args *o, const char *line)
{
    sim_ios_cmd c;
    core_err err = {0};
    if (sim_ios_parse(line, &c, &err) != 0) {
        printf("error: %s\n", err.msg);
        return -1;
    }
    sim_ios_answer a;
    char buf[640];
    switch (c.command) {
    case SIM_IOS_NONE: return 0;
    case SIM_IOS_QUIT: return 2;
    case SIM_IOS_HELP: fputs(sim_ios_help(), stdout); return 0;
    case SIM_IOS_WAIT: {
        struct timespec ts = {(time_t)c.wait_s, (long)((c.wait_s - (double)(time_t)c.wait_s) * 1e9)};
        nanosleep(&ts, NULL);
        return 0;
    }
    case SIM_IOS_STATUS:
        if (sim_ios_status(io, o->timeout_s, &a, &err) != 0) {
            printf("error: %s\n", err.msg);
            return -1;
        }
        sim_ios_format(&a, 1, buf, sizeof buf);
        printf("status: %s\n", buf);
        return 0;
    default: break;
    }
    int rc = sim_ios_send(io, &c, o->timeout_s, &a, &err);
    if (rc < 0) {
        printf("error: %s\n", err.msg);
        return -1;
    }
    sim_ios_format(&a, 0, buf, sizeof buf);
    printf("%s\n", buf);
    return rc;
}

/* The lines of f (a prompt on a terminal): the run's exit status so far. */
static int ios_file(sim_ios *io, const ios_args *o, FILE *f, int prompt, int *refused)
{
    char line[1100];
    for (;;) {
        if (prompt) {
            printf("ios> ");
            fflush(stdout);
        }
        if (!fgets(line, sizeof line, f))
            return 0;
        int rc = ios_line(io, o, line);
        fflush(stdout);
        if (rc == 2)
            return 0;
        if (rc == 1)
            *refused = 1;
        if (rc < 0 && !prompt)
            return 1; /* a script stops; at the terminal the instructor types again */
    }
}

int cmd_ios(int argc, char **argv)
{
    ios_args o;
    int rc = ios_parse_args(argc, argv, &o);
    if (rc >= 0)
        return rc;
    FILE *script = NULL;
    if (o.script && !(script = fopen(o.script, "r"))) {
        fprintf(stderr, "ios: %s: cannot open\n", o.script);
        return 1;
    }
    core_err err = {0};
    sim_ios *io = sim_ios_create(o.url, &err);
    if (!io) {
        fprintf(stderr, "ios: %s\n", err.msg);
        if (script)
            fclose(script);
        return 1;
    }
    int refused = 0, fail = 0, quit = 0;
    for (int i = 0; i < o.ncmd && !fail && !quit; i++) {
        int r = ios_line(io, &o, o.cmd[i]);
        fflush(stdout);
        refused |= r == 1;
        fail = r < 0;
        quit = r == 2;
    }
    if (!fail && !quit && script)
        fail = ios_file(io, &o, script, 0, &refused);
    if (!fail && !quit && !o.ncmd && !script)
        fail = ios_file(io, &o, stdin, isatty(STDIN_FILENO), &refused);
    if (script)
        fclose(script);
    sim_ios_destroy(io);
    return fail || refused ? 1 : 0;
}
