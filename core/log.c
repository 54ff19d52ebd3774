/* log.c -- the log callback and error buffers. Libraries never print: they
 * format a line and hand it to the caller's sink, which decides where it goes.
 * A line or an error may hold a name from the command line, a file or the
 * network: every byte a terminal would act on (control characters, DEL, and
 * bytes above 0x7f, which no message of disim's own holds) is written as
 * \xNN, so whatever prints it prints text. */
#include "core.h"

#include <stdio.h>

/* in into out (n bytes, NUL-terminated), the bytes a terminal acts on as
 * \xNN, cut at a whole escape. */
static void printable(const char *in, char *out, size_t n)
{
    static const char hex[] = "0123456789abcdef";
    size_t o = 0;
    for (const unsigned char *p = (const unsigned char *)in; *p; p++) {
        int esc = *p < 0x20 || *p >= 0x7f;
        if (o + (esc ? 4 : 1) >= n)
            break;
        if (esc) {
            out[o++] = '\\';
            out[o++] = 'x';
            out[o++] = hex[*p >> 4];
            out[o++] = hex[*p & 15];
        } else {
            out[o++] = (char)*p;
        }
    }
    out[o] = '\0';
}

void core_log_msg(const core_log *log, int level, const char *fmt, ...)
{
    if (!log || !log->fn || level > log->max_level)
        return;
    char buf[1024], shown[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    printable(buf, shown, sizeof shown);
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
        printable(buf, err->msg, sizeof err->msg);
        err->code = code;
    }
    return code;
}
