/* str.c -- a growing text buffer for the reports (core_str). The reports
 * were built in buffers sized up front from their row counts; a longer
 * preamble then made the field table drop its rows without a word. Here
 * the buffer grows to what is written, and a failed allocation is kept, not
 * hidden. */
#include "core.h"

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

int core_str_printf(core_str *b, const char *fmt, ...)
{
    if (b->failed)
        return -1;
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(b->s ? b->s + b->len : NULL, b->s ? b->cap - b->len : 0, fmt, ap);
    va_end(ap);
    if (n < 0) {
        b->failed = 1;
        return -1;
    }
    if (b->s && (size_t)n < b->cap - b->len) {
        b->len += (size_t)n;
        return 0;
    }
    size_t need = b->len + (size_t)n + 1, cap = b->cap ? b->cap : 256;
    while (cap < need && cap <= SIZE_MAX / 2)
        cap *= 2;
    if (cap < need)
        cap = need;
    char *p = realloc(b->s, cap);
    if (!p) {
        b->failed = 1;
        if (b->s)
            b->s[b->len] = '\0';
        return -1;
    }
    b->s = p;
    b->cap = cap;
    va_start(ap, fmt);
    vsnprintf(b->s + b->len, b->cap - b->len, fmt, ap);
    va_end(ap);
    b->len += (size_t)n;
    return 0;
}

char *core_str_take(core_str *b)
{
    char *s = b->s;
    if (b->failed) {
        free(s);
        s = NULL;
    } else if (!s) {
        s = calloc(1, 1);
    }
    b->s = NULL;
    b->len = b->cap = 0;
    b->failed = 0;
    return s;
}
