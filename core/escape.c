/* escape.c -- text from files or the network made safe to echo: a byte
 * that a terminal would act on (a control character, DEL) or that is not
 * ASCII is written as \xNN, so that what a host on the network sends can
 * be shown, logged and sent on without moving a cursor, clearing a screen
 * or changing a title. A backslash stays as it is: escaping is idempotent
 * (text escaped twice, as an error message that quotes another one, reads
 * the same), at the cost that a name holding the four characters \x1b
 * shows as one holding ESC would. */
#include "core.h"

#include <stdio.h>

size_t core_escape(const char *in, char *out, size_t n)
{
    size_t k = 0;
    if (n == 0)
        return 0;
    for (const unsigned char *p = (const unsigned char *)(in ? in : ""); *p; p++) {
        char buf[5];
        size_t m;
        if (*p < 0x20 || *p >= 0x7f)
            m = (size_t)snprintf(buf, sizeof buf, "\\x%02x", *p);
        else
            buf[0] = (char)*p, buf[1] = '\0', m = 1;
        if (k + m >= n)
            break; /* cut at a whole escape, never inside one */
        for (size_t i = 0; i < m; i++)
            out[k++] = buf[i];
    }
    out[k] = '\0';
    return k;
}
