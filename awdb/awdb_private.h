/* awdb_private.h -- shared between awdb.c and builder.c. */
#ifndef DISIM_AWDB_PRIVATE_H
#define DISIM_AWDB_PRIVATE_H

#include "awdb.h"

#include <pthread.h>
#include <stdio.h>

#define AWDB_PATH 1024
/* A key as INI text, with a loaded-disk table (8 x 12 + 8 numbers). */
#define AWDB_KEY_TEXT 4096

struct awdb {
    char dir[AWDB_PATH];
    const core_log *log;
    pthread_mutex_t lock; /* guards the verified-field cache */
    struct verified {
        char name[160];
        long long mtime_ns, size;
    } *cache;
    size_t ncache, capcache;
};

/* snprintf that reports truncation (< 0) instead of warning about it: paths
 * are bounded at awdb_open and names by awdb_key_name, so it does not happen,
 * and where it could, a truncated path must not be used silently. */
int awdb_fmt(char *out, size_t n, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* Write text to path atomically (temporary file in the same folder, fsync,
 * rename). */
int awdb_write_atomic(const char *path, const char *text, core_err *err);
/* Key as INI text (section [key]) and back; the reader names file:line. */
void awdb_key_format(const awdb_key *k, char *buf, size_t n);
int awdb_key_read(core_ini *ini, awdb_key *k, core_err *err);
/* A field's checksum record (NAME.sum: [field] size, crc64 as 16 hex
 * digits, then its [key]; key NULL skips the key) from its parsed text:
 * 0, or < 0 with err naming the file, line and key. */
int awdb_sum_read(core_ini *ini, uint64_t *size, uint64_t *crc, awdb_key *key, core_err *err);
/* Build a path under the database folder. */
void awdb_path(const awdb *db, char *out, size_t n, const char *sub, const char *name,
               const char *ext);

#endif
