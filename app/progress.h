/* progress.h -- the status line of a command waiting on the airwake
 * database (disim shol while its builder works in another process).
 *
 * On a terminal, one line rewritten in place (\r, cleared) about once a
 * second: the field waited for, its build's iteration of the cap, residual,
 * percent and the time left (or that it is queued, and what is building
 * instead), the database's fields ready and requests queued, and the time
 * waited. In a log (not a terminal) nothing: the coupling's one "waiting for
 * airwake NAME" line per field stays the only trace. What is shown comes
 * from awdb_progress_read; the builder publishes it. */
#ifndef DISIM_APP_PROGRESS_H
#define DISIM_APP_PROGRESS_H

#include "awdb.h"

#include <stddef.h>

typedef struct app_progress {
    awdb *db;
    int tty;          /* 1: standard error is a terminal (else the callback prints nothing) */
    int columns;      /* width the line is cut to (0: $COLUMNS, else the terminal's, else 80) */
    double period_s;  /* least interval between two lines (1 s) */
    double last_s;    /* waited_s of the last line; < 0: none yet */
    char name[AWDB_NAME_MAX]; /* the key of the last line */
} app_progress;

void app_progress_init(app_progress *p, awdb *db, int tty);
/* couple_settings.wait_fn (user: an app_progress): the line on a terminal,
 * about once a second and at the start of each wait. */
void app_progress_wait(void *user, const awdb_key *key, double waited_s);
/* The status line without \r (at most n - 1 bytes), for the key named name
 * (awdb_key_name) waited for waited_s against the database state p. */
void app_progress_format(const awdb_progress *p, const char *name, double waited_s, char *buf, size_t n);

#endif
