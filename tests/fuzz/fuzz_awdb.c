/* fuzz_awdb.c -- libFuzzer harness of the airwake database's records, read
 * from their text in memory as awdb reads its files' (core_ini_parse):
 * the first byte chooses, the rest is the record:
 *   even  a build request (queue/, running/: a [key] section): awdb_key_read,
 *         then awdb_key_canon and awdb_key_name, as the builder does
 *   odd   a field's checksum record (fields/NAME.sum: [field] size and crc64,
 *         then the [key]): awdb_sum_read, then the key as above
 * Checked, beyond no crash, hang, leak or sanitizer report: a refused record
 * says why; a key that is canonical names a file inside its folder (a stem
 * of at most AWDB_NAME_MAX - 1 characters, no '/', not starting with '.'),
 * stays the same key when made canonical again, and reads back as itself
 * from the text awdb writes for it (awdb_key_format). */
#include "awdb_private.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check_key(awdb_key *k)
{
    core_err err = {0};
    if (awdb_key_canon(k, &err) != 0) {
        if (!err.msg[0])
            abort();
        return;
    }
    char name[AWDB_NAME_MAX + 64], again[AWDB_NAME_MAX + 64];
    awdb_key_name(k, name, sizeof name);
    size_t len = strlen(name);
    if (len == 0 || len >= AWDB_NAME_MAX || strchr(name, '/') || name[0] == '.')
        abort(); /* the stem would not name a file inside the database's folder */
    awdb_key k2 = *k;
    if (awdb_key_canon(&k2, &err) != 0)
        abort(); /* canonical, then refused */
    awdb_key_name(&k2, again, sizeof again);
    if (strcmp(name, again))
        abort(); /* canonical twice is not the same key */
    /* what awdb writes for the key reads back as the same key */
    char text[8192];
    awdb_key_format(k, text, sizeof text);
    core_ini *ini = core_ini_parse(text, strlen(text), "fuzz/written.req", &err);
    awdb_key k3;
    if (!ini || awdb_key_read(ini, &k3, &err) != 0 || awdb_key_canon(&k3, &err) != 0)
        abort(); /* awdb cannot read what it writes */
    core_ini_destroy(ini);
    awdb_key_name(&k3, again, sizeof again);
    if (strcmp(name, again))
        abort(); /* the written key reads back as another */
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    core_err err = {0};
    core_ini *ini = core_ini_parse((const char *)data + 1, size - 1, "fuzz/record", &err);
    if (!ini) {
        if (!err.msg[0])
            abort();
        return 0;
    }
    awdb_key k;
    int rc;
    if (data[0] % 2 == 0) {
        rc = awdb_key_read(ini, &k, &err);
        if (rc == 0)
            rc = core_ini_check_unused(ini, &err);
    } else {
        uint64_t sz = 0, crc = 0;
        rc = awdb_sum_read(ini, &sz, &crc, &k, &err);
    }
    core_ini_destroy(ini);
    if (rc != 0) {
        if (!err.msg[0])
            abort();
        return 0;
    }
    check_key(&k);
    return 0;
}
