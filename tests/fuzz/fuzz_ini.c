/* fuzz_ini.c -- libFuzzer harness for the INI reader (core_ini_parse, the
 * reader core_ini_load runs on a file's text) and every typed getter on
 * every entry it returns: no crash, no sanitizer report, and a value that
 * loads is text (no NUL, no control character but tab and CR). The input
 * is parsed in memory. Build: -DDISIM_FUZZ=ON with clang
 * (tests/fuzz/README.md). */
#include "core.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void check_text(const char *s)
{
    for (const unsigned char *p = (const unsigned char *)s; *p; p++)
        if ((*p < 0x20 && *p != '\t' && *p != '\r') || *p == 0x7F)
            abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    core_err err = {0};
    core_ini *ini = core_ini_parse((const char *)data, size, "fuzz/input.ini", &err);
    if (!ini)
        return 0;
    for (size_t i = 0; i < core_ini_count(ini); i++) {
        const core_ini_entry *e = core_ini_at(ini, i);
        check_text(e->section);
        check_text(e->key);
        check_text(e->value);
        char sec[256], key[256], s[256];
        snprintf(sec, sizeof sec, "%s", e->section);
        snprintf(key, sizeof key, "%s", e->key);
        double d, l[8], r[64];
        long n;
        int b, k, cnt;
        core_ini_get_double(ini, sec, key, 1, -1e300, 1e300, &d, &err);
        core_ini_get_int(ini, sec, key, 1, -1000000, 1000000, &n, &err);
        core_ini_get_bool(ini, sec, key, 1, &b, &err);
        core_ini_get_enum(ini, sec, key, 1, "a|bb|single|sweep", &k, &err);
        core_ini_get_string(ini, sec, key, 1, s, sizeof s, &err);
        core_ini_get_name(ini, sec, key, 1, s, sizeof s, &err);
        core_ini_get_doubles(ini, sec, key, 1, -1e6, 1e6, l, 8, &cnt, &err);
        core_ini_get_path(ini, sec, key, 1, s, sizeof s, &err);
        core_parse_range(e->value, r, 64, &cnt);
    }
    core_ini_check_unused(ini, &err);
    core_ini_destroy(ini);
    return 0;
}
