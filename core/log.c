/* log.c -- the log callback and error buffers. Libraries never print: they
 * format a line and hand it to the caller's sink, which decides where it goes.
 * A line or an error may hold a name from the command line, a file or the
 * network: every byte a terminal would act on (control characters, DEL, and
 * bytes above 0x7f, which no message of disim's own holds) is written as
 * \xNN (core_escape), so whatever prints it prints text. */
#include "core.h"

#include <stdio.h>

void core_log_msg(const core_log *log, int level, const char *fmt, ...)
{
    if (!log || !log->fn || level > log->max_level)
        return;
    char buf[1024], shown[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    core_escape(buf, shown, sizeof shown);
    log->fn(log->user, level, shown);
}

int core_err_set(core_err *err, int code, const char *fmt, ...)
{
    if (err) {
        char buf[sizeof err->msg];
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(buf, sizeof buf, fmt, ap);
        va_end(ap);
        core_escape(buf, err->msg, sizeof err->msg);
        err->code = code;
    }
    return code;
}
