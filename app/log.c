/* log.c -- the disim command's log line on standard error and its number
 * flags, shared by every subcommand. */
#include "cmds.h"
#include "core.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>

void app_log_stderr(void *user, int level, const char *msg)
{
    static const char *names[] = {"error", "warning", "info", "debug"};
    const app_log *l = user;
    const char *name = names[level < CORE_LOG_ERROR ? 0 : level > CORE_LOG_DEBUG ? 3 : level];
    int tty = l && l->tty;
    if (l && l->prefix && l->prefix[0])
        fprintf(stderr, "%s%s: %s: %s\n", tty ? "\r\033[K" : "", l->prefix, name, msg);
    else
        fprintf(stderr, "%s%s: %s\n", tty ? "\r\033[K" : "", name, msg);
}

int app_parse_double(const char *prefix, const char *flag, const char *s, double lo, double hi, double *out)
{
    char *end;
    double v = strtod(s, &end);
    if (end == s || *end || !(v >= lo && v <= hi)) {
        fprintf(stderr, "%s: %s: expected a number in [%g, %g], got '%s'\n", prefix, flag, lo, hi, s);
        return -1;
    }
    *out = v;
    return 0;
}

int app_parse_int(const char *prefix, const char *flag, const char *s, int lo, int hi, int *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (end == s || *end || v < lo || v > hi) {
        fprintf(stderr, "%s: %s: expected a whole number in [%d, %d], got '%s'\n", prefix, flag, lo, hi, s);
        return -1;
    }
    *out = (int)v;
    return 0;
}
