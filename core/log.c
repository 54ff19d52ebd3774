/* log.c -- the log callback and error buffers. Libraries never print: they
 * format a line and hand it to the caller's sink, which decides where it goes. */
#include "core.h"

#include <stdio.h>

void core_log_msg(const core_log *log, int level, const char *fmt, ...)
{
    if (!log || !log->fn || level > log->max_level)
        return;
    char buf[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    log->fn(log->user, level, buf);
}

int core_err_set(core_err *err, int code, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
        err->code = code;
    }
    return code;
}
