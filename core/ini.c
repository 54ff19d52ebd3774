/* ini.c -- INI files read whole with libinih, every entry kept with its line
 * number, and typed getters that name file, line, section, key and what was
 * expected. Consumed entries are marked so that a final check reports the
 * first unknown key or section (a typo never passes silently). */
#include "core.h"

#include <ini.h>

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

struct core_ini {
    char *path;
    char *dir; /* folder of path, for relative paths */
    core_ini_entry *e;
    size_t n, cap;
};

typedef struct reader_state {
    const unsigned char *p; /* the text, len bytes; pos: the next to read */
    size_t len, pos;
    int line;
    int too_long_line; /* first line that did not fit inih's buffer */
    int bad_line, bad_col, bad_byte; /* the first byte that is not text */
    const char *bad_why;
} reader_state;

/* Bytes of the UTF-8 sequence starting at s (at most n bytes there), or 0
 * if it is not one: overlong forms, surrogates and code points past
 * U+10FFFF are refused. A sequence cut by the end of a full buffer counts
 * as whole (the line is refused as too long anyway). */
static int utf8_len(const unsigned char *s, size_t n, int cut)
{
    unsigned c = s[0];
    int k;
    unsigned lo = 0x80, hi = 0xBF;
    if (c >= 0xC2 && c <= 0xDF)
        k = 2;
    else if (c >= 0xE0 && c <= 0xEF) {
        k = 3;
        if (c == 0xE0)
            lo = 0xA0;
        else if (c == 0xED)
            hi = 0x9F;
    } else if (c >= 0xF0 && c <= 0xF4) {
        k = 4;
        if (c == 0xF0)
            lo = 0x90;
        else if (c == 0xF4)
            hi = 0x8F;
    } else
        return 0;
    for (int i = 1; i < k; i++) {
        if ((size_t)i >= n)
            return cut ? (int)n : 0;
        unsigned b = s[i];
        if (b < (i == 1 ? lo : 0x80) || b > (i == 1 ? hi : 0xBF))
            return 0;
    }
    return k;
}

/* The first byte of line that is not text: a NUL, a control character
 * other than tab, CR and LF, or a byte that is not UTF-8. */
static void check_text(reader_state *rs, const unsigned char *s, size_t len, int cut)
{
    for (size_t i = 0; i < len && !rs->bad_line;) {
        unsigned c = s[i];
        const char *why = NULL;
        int step = 1;
        if (c == 0)
            why = "a NUL byte (a binary file?)";
        else if ((c < 0x20 && c != '\t' && c != '\r' && c != '\n') || c == 0x7F)
            why = "a control character";
        else if (c >= 0x80 && !(step = utf8_len(s + i, len - i, cut)))
            why = "a byte that is not UTF-8";
        if (why) {
            rs->bad_line = rs->line;
            rs->bad_col = (int)i + 1;
            rs->bad_byte = (int)c;
            rs->bad_why = why;
        }
        i += (size_t)step;
    }
}

/* inih calls the reader once per line; counting calls gives the line number
 * the handler is about to see (the Debian build has no INI_HANDLER_LINENO).
 * The line is copied byte by byte up to its LF, as a NUL in it must be seen;
 * the first byte that is not text ends the reading (the text is refused). */
static char *reader(char *str, int num, void *stream)
{
    reader_state *rs = stream;
    if (rs->bad_line || rs->pos >= rs->len)
        return NULL;
    size_t len = 0;
    while (len + 1 < (size_t)num && rs->pos < rs->len) {
        char c = (char)rs->p[rs->pos++];
        str[len++] = c;
        if (c == '\n')
            break;
    }
    str[len] = '\0';
    rs->line++;
    int full = len + 1 == (size_t)num && str[len - 1] != '\n';
    check_text(rs, (const unsigned char *)str, len, full);
    if (full && rs->pos < rs->len && rs->p[rs->pos] != '\n') {
        if (!rs->too_long_line)
            rs->too_long_line = rs->line;
        while (rs->pos < rs->len && rs->p[rs->pos] != '\n')
            rs->pos++;
    }
    if (full && rs->pos < rs->len)
        rs->pos++; /* the LF that ends the long line */
    if (rs->bad_line)
        str[0] = '\0'; /* inih sees an empty line, then the end */
    return str;
}

typedef struct load_ctx {
    core_ini *ini;
    reader_state *rs;
    int oom;
    int dup_line, dup_first; /* a key given twice in a section: its lines */
    char dup_section[64], dup_key[64];
} load_ctx;

static int handler(void *user, const char *section, const char *name, const char *value)
{
    load_ctx *c = user;
    core_ini *ini = c->ini;
    /* A key given twice would silently take its last value; inih also calls
     * back with the same key for an indented line (a continuation), which
     * would replace a value without a word. Both are refused. */
    for (size_t i = 0; i < ini->n; i++)
        if (!strcmp(ini->e[i].section, section) && !strcmp(ini->e[i].key, name)) {
            if (c->dup_line) /* the first repeat is the one reported */
                return 0;
            c->dup_line = c->rs->line;
            c->dup_first = ini->e[i].line;
            snprintf(c->dup_section, sizeof c->dup_section, "%s", section);
            snprintf(c->dup_key, sizeof c->dup_key, "%s", name);
            return 0;
        }
    if (ini->n == ini->cap) {
        size_t cap = ini->cap ? 2 * ini->cap : 32;
        core_ini_entry *e = realloc(ini->e, cap * sizeof *e);
        if (!e) {
            c->oom = 1;
            return 0;
        }
        ini->e = e;
        ini->cap = cap;
    }
    core_ini_entry *e = &ini->e[ini->n];
    e->section = strdup(section);
    e->key = strdup(name);
    e->value = strdup(value);
    e->line = c->rs->line;
    e->used = 0;
    if (!e->section || !e->key || !e->value) {
        free((void *)e->section);
        free((void *)e->key);
        free((void *)e->value);
        c->oom = 1;
        return 0;
    }
    ini->n++;
    return 1;
}

core_ini *core_ini_load(const char *path, core_err *err)
{
    size_t len = 0;
    char *text = core_file_read(path, CORE_INI_MAX_BYTES, &len, err);
    if (!text)
        return NULL;
    core_ini *ini = core_ini_parse(text, len, path, err);
    free(text);
    return ini;
}

core_ini *core_ini_parse(const char *text, size_t len, const char *path, core_err *err)
{
    if ((long long)len > CORE_INI_MAX_BYTES) {
        core_err_set(err, -1, "%s: %zu bytes, larger than the %lld bytes a file of this kind may have", path, len,
                     CORE_INI_MAX_BYTES);
        return NULL;
    }
    core_ini *ini = calloc(1, sizeof *ini);
    if (!ini) {
        core_err_set(err, -1, "%s: out of memory", path);
        return NULL;
    }
    ini->path = strdup(path);
    ini->dir = strdup(path);
    if (!ini->path || !ini->dir) {
        core_ini_destroy(ini);
        core_err_set(err, -1, "%s: out of memory", path);
        return NULL;
    }
    char *slash = strrchr(ini->dir, '/');
    if (slash)
        slash[1] = '\0';
    else
        ini->dir[0] = '\0';
    reader_state rs = {(const unsigned char *)text, len, 0, 0, 0, 0, 0, 0, NULL};
    load_ctx c = {ini, &rs, 0, 0, 0, "", ""};
    int rc = ini_parse_stream(reader, &rs, handler, &c);
    if (rs.bad_line) {
        if (rs.bad_byte == 0)
            core_err_set(err, -1, "%s:%d:%d: %s: expected text", path, rs.bad_line, rs.bad_col,
                         rs.bad_why);
        else
            core_err_set(err, -1, "%s:%d:%d: byte 0x%02X, %s: expected UTF-8 text", path, rs.bad_line,
                         rs.bad_col, (unsigned)rs.bad_byte, rs.bad_why);
        core_ini_destroy(ini);
        return NULL;
    }
    if (c.oom) {
        core_ini_destroy(ini);
        core_err_set(err, -1, "%s: out of memory", path);
        return NULL;
    }
    if (rs.too_long_line) {
        core_err_set(err, -1, "%s:%d: line longer than %d characters", path, rs.too_long_line,
                     INI_MAX_LINE - 1);
        core_ini_destroy(ini);
        return NULL;
    }
    /* inih returns the first line in error: a syntax error before the
     * first repeat is reported as such */
    if (c.dup_line && (rc == 0 || rc >= c.dup_line)) {
        core_err_set(err, -1,
                     "%s:%d: [%s] %s: given again (first at line %d): expected each key once in a section "
                     "(an indented line continues the key above it)",
                     path, c.dup_line, c.dup_section, c.dup_key, c.dup_first);
        core_ini_destroy(ini);
        return NULL;
    }
    if (rc != 0) {
        core_err_set(err, -1,
                     "%s:%d: syntax error: expected '[section]', 'key = value' or a comment", path,
                     rc);
        core_ini_destroy(ini);
        return NULL;
    }
    return ini;
}

void core_ini_destroy(core_ini *ini)
{
    if (!ini)
        return;
    for (size_t i = 0; i < ini->n; i++) {
        free((void *)ini->e[i].section);
        free((void *)ini->e[i].key);
        free((void *)ini->e[i].value);
    }
    free(ini->e);
    free(ini->path);
    free(ini->dir);
    free(ini);
}

const char *core_ini_path(const core_ini *ini) { return ini->path; }
size_t core_ini_count(const core_ini *ini) { return ini->n; }
const core_ini_entry *core_ini_at(const core_ini *ini, size_t i) { return i < ini->n ? &ini->e[i] : NULL; }

static core_ini_entry *find(const core_ini *ini, const char *section, const char *key)
{
    for (size_t i = ini->n; i-- > 0;)
        if (strcmp(ini->e[i].section, section) == 0 && strcmp(ini->e[i].key, key) == 0)
            return &ini->e[i];
    return NULL;
}

const core_ini_entry *core_ini_find(const core_ini *ini, const char *section, const char *key)
{
    return find(ini, section, key);
}

int core_ini_has_section(const core_ini *ini, const char *section)
{
    for (size_t i = 0; i < ini->n; i++)
        if (strcmp(ini->e[i].section, section) == 0)
            return 1;
    return 0;
}

/* Levenshtein distance, capped: keys are short. */
static int edit_distance(const char *a, const char *b)
{
    size_t la = strlen(a), lb = strlen(b);
    if (la > 63 || lb > 63)
        return 99;
    int d[64][64];
    for (size_t i = 0; i <= la; i++)
        d[i][0] = (int)i;
    for (size_t j = 0; j <= lb; j++)
        d[0][j] = (int)j;
    for (size_t i = 1; i <= la; i++)
        for (size_t j = 1; j <= lb; j++) {
            int c = d[i - 1][j - 1] + (a[i - 1] != b[j - 1]);
            if (d[i - 1][j] + 1 < c)
                c = d[i - 1][j] + 1;
            if (d[i][j - 1] + 1 < c)
                c = d[i][j - 1] + 1;
            d[i][j] = c;
        }
    return d[la][lb];
}

/* Look up a key (each is there once: core_ini_load refuses repeats), handle absence. Returns 0 with *e
 * set, 1 if absent and optional, < 0 if absent and required. */
static int lookup(core_ini *ini, const char *section, const char *key, int required,
                  core_ini_entry **e, core_err *err)
{
    *e = NULL;
    for (size_t i = 0; i < ini->n; i++)
        if (strcmp(ini->e[i].section, section) == 0 && strcmp(ini->e[i].key, key) == 0) {
            ini->e[i].used = 1;
            *e = &ini->e[i];
        }
    if (*e)
        return 0;
    if (!required)
        return 1;
    /* A required key is often missing because it was mistyped: point at the
     * unconsumed key of the same section that is closest to it. */
    const core_ini_entry *best = NULL;
    int best_d = 3;
    for (size_t i = 0; i < ini->n; i++) {
        const core_ini_entry *c = &ini->e[i];
        if (c->used || strcmp(c->section, section) != 0)
            continue;
        int d = edit_distance(c->key, key);
        if (d < best_d) {
            best_d = d;
            best = c;
        }
    }
    if (best)
        return core_err_set(err, -1, "%s:%d: [%s] %s: unknown key (a typo of the required key '%s'?)",
                            ini->path, best->line, section, best->key, key);
    return core_err_set(err, -1, "%s: [%s] %s: missing required key", ini->path, section, key);
}

/* The next item of a list separated by sep, cut in place; *p moves past it
 * (NULL after the last item). Unlike strtok an empty item ("1,,2", a
 * trailing comma) comes back as "", so the caller reports it rather than
 * reading a shorter list whose items have moved. */
static char *next_item(char **p, char sep)
{
    char *s = *p;
    if (!s)
        return NULL;
    char *q = strchr(s, sep);
    if (q) {
        *q = '\0';
        *p = q + 1;
    } else {
        *p = NULL;
    }
    return s;
}

/* A decimal number: [+-]digits[.digits][(e|E)[+-]digits], blanks around.
 * strtod alone would also take hexadecimal (0x14 as 20), "inf" and "nan". */
static int is_decimal(const char *s)
{
    while (*s == ' ' || *s == '\t')
        s++;
    if (*s == '+' || *s == '-')
        s++;
    int digits = 0;
    while (*s >= '0' && *s <= '9')
        s++, digits++;
    if (*s == '.')
        for (s++; *s >= '0' && *s <= '9'; s++)
            digits++;
    if (!digits)
        return 0;
    if (*s == 'e' || *s == 'E') {
        s++;
        if (*s == '+' || *s == '-')
            s++;
        if (!(*s >= '0' && *s <= '9'))
            return 0;
        while (*s >= '0' && *s <= '9')
            s++;
    }
    while (*s == ' ' || *s == '\t')
        s++;
    return *s == '\0';
}

static int parse_double(const char *s, double *out)
{
    if (!is_decimal(s))
        return -1;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || errno == ERANGE || !isfinite(v))
        return -1;
    while (*end == ' ' || *end == '\t')
        end++;
    if (*end)
        return -1;
    *out = v;
    return 0;
}

int core_ini_get_double(core_ini *ini, const char *section, const char *key, int required,
                        double min, double max, double *out, core_err *err)
{
    core_ini_entry *e;
    int rc = lookup(ini, section, key, required, &e, err);
    if (rc)
        return rc;
    double v;
    if (parse_double(e->value, &v))
        return core_err_set(err, -1, "%s:%d: [%s] %s = '%s': expected a number", ini->path,
                            e->line, section, key, e->value);
    if (v < min || v > max)
        return core_err_set(err, -1, "%s:%d: [%s] %s = %g: out of range, expected %g to %g",
                            ini->path, e->line, section, key, v, min, max);
    *out = v;
    return 0;
}

int core_ini_get_int(core_ini *ini, const char *section, const char *key, int required, long min,
                     long max, long *out, core_err *err)
{
    core_ini_entry *e;
    int rc = lookup(ini, section, key, required, &e, err);
    if (rc)
        return rc;
    char *end;
    errno = 0;
    long v = strtol(e->value, &end, 10);
    if (end == e->value || *end || errno == ERANGE)
        return core_err_set(err, -1, "%s:%d: [%s] %s = '%s': expected an integer", ini->path,
                            e->line, section, key, e->value);
    if (v < min || v > max)
        return core_err_set(err, -1, "%s:%d: [%s] %s = %ld: out of range, expected %ld to %ld",
                            ini->path, e->line, section, key, v, min, max);
    *out = v;
    return 0;
}

int core_ini_get_bool(core_ini *ini, const char *section, const char *key, int required, int *out,
                      core_err *err)
{
    core_ini_entry *e;
    int rc = lookup(ini, section, key, required, &e, err);
    if (rc)
        return rc;
    const char *v = e->value;
    if (!strcasecmp(v, "true") || !strcasecmp(v, "yes") || !strcasecmp(v, "on") || !strcmp(v, "1"))
        *out = 1;
    else if (!strcasecmp(v, "false") || !strcasecmp(v, "no") || !strcasecmp(v, "off") ||
             !strcmp(v, "0"))
        *out = 0;
    else
        return core_err_set(err, -1, "%s:%d: [%s] %s = '%s': expected true or false", ini->path,
                            e->line, section, key, v);
    return 0;
}

int core_ini_get_enum(core_ini *ini, const char *section, const char *key, int required,
                      const char *choices, int *out, core_err *err)
{
    core_ini_entry *e;
    int rc = lookup(ini, section, key, required, &e, err);
    if (rc)
        return rc;
    size_t vl = strlen(e->value);
    const char *p = choices;
    for (int idx = 0;; idx++) {
        const char *bar = strchr(p, '|');
        size_t len = bar ? (size_t)(bar - p) : strlen(p);
        if (len == vl && strncmp(p, e->value, len) == 0) {
            *out = idx;
            return 0;
        }
        if (!bar)
            break;
        p = bar + 1;
    }
    return core_err_set(err, -1, "%s:%d: [%s] %s = '%s': expected one of %s", ini->path, e->line,
                        section, key, e->value, choices);
}

int core_ini_get_string(core_ini *ini, const char *section, const char *key, int required,
                        char *out, size_t n, core_err *err)
{
    core_ini_entry *e;
    int rc = lookup(ini, section, key, required, &e, err);
    if (rc)
        return rc;
    if (!e->value[0])
        return core_err_set(err, -1, "%s:%d: [%s] %s: expected a non-empty value", ini->path,
                            e->line, section, key);
    if (strlen(e->value) >= n)
        return core_err_set(err, -1, "%s:%d: [%s] %s: value longer than %zu characters",
                            ini->path, e->line, section, key, n - 1);
    strcpy(out, e->value);
    return 0;
}

int core_ini_get_name(core_ini *ini, const char *section, const char *key, int required, char *out,
                      size_t n, core_err *err)
{
    int rc = core_ini_get_string(ini, section, key, required, out, n, err);
    if (rc)
        return rc;
    int ok = out[0] != '.';
    for (const char *p = out; *p && ok; p++)
        ok = (*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') ||
             *p == '_' || *p == '-' || *p == '.';
    if (!ok)
        return core_err_set(err, -1,
                            "%s:%d: [%s] %s = '%s': expected a name of letters, digits, '_', '-' or '.', "
                            "not starting with '.' (it names files and folders)",
                            ini->path, core_ini_find(ini, section, key)->line, section, key, out);
    return 0;
}

int core_ini_get_doubles(core_ini *ini, const char *section, const char *key, int required,
                         double min, double max, double *out, int nmax, int *count, core_err *err)
{
    core_ini_entry *e;
    int rc = lookup(ini, section, key, required, &e, err);
    if (rc)
        return rc;
    if (!e->value[0])
        return core_err_set(err, -1, "%s:%d: [%s] %s: expected a comma-separated list of numbers",
                            ini->path, e->line, section, key);
    char buf[INI_MAX_LINE + 1];
    snprintf(buf, sizeof buf, "%s", e->value);
    int k = 0;
    char *rest = buf;
    for (char *tok; (tok = next_item(&rest, ','));) {
        while (*tok == ' ' || *tok == '\t')
            tok++;
        double v;
        if (k >= nmax)
            return core_err_set(err, -1, "%s:%d: [%s] %s: more than %d values", ini->path,
                                e->line, section, key, nmax);
        if (parse_double(tok, &v))
            return core_err_set(err, -1, "%s:%d: [%s] %s: item %d '%s': expected a number",
                                ini->path, e->line, section, key, k + 1, tok);
        if (v < min || v > max)
            return core_err_set(err, -1,
                                "%s:%d: [%s] %s: item %d = %g: out of range, expected %g to %g",
                                ini->path, e->line, section, key, k + 1, v, min, max);
        out[k++] = v;
    }
    *count = k;
    return 0;
}

int core_ini_get_path(core_ini *ini, const char *section, const char *key, int required,
                      char *out, size_t n, core_err *err)
{
    core_ini_entry *e;
    int rc = lookup(ini, section, key, required, &e, err);
    if (rc)
        return rc;
    int w = e->value[0] == '/' ? snprintf(out, n, "%s", e->value)
                               : snprintf(out, n, "%s%s", ini->dir, e->value);
    if (w < 0 || (size_t)w >= n)
        return core_err_set(err, -1, "%s:%d: [%s] %s: path too long", ini->path, e->line,
                            section, key);
    struct stat st;
    if (stat(out, &st) != 0)
        return core_err_set(err, -1, "%s:%d: [%s] %s = '%s': file not found (looked for %s)",
                            ini->path, e->line, section, key, e->value, out);
    core_err why = {0};
    if (core_file_check_stat(out, &st, -1, &why))
        return core_err_set(err, -1, "%s:%d: [%s] %s = '%s': %s", ini->path, e->line, section, key,
                            e->value, why.msg);
    return 0;
}

void core_ini_skip_section(core_ini *ini, const char *section)
{
    for (size_t i = 0; i < ini->n; i++)
        if (strcmp(ini->e[i].section, section) == 0)
            ini->e[i].used = 1;
}

int core_ini_check_unused(const core_ini *ini, core_err *err)
{
    for (size_t i = 0; i < ini->n; i++) {
        const core_ini_entry *e = &ini->e[i];
        if (e->used)
            continue;
        int known_section = 0;
        for (size_t j = 0; j < ini->n; j++)
            if (ini->e[j].used && strcmp(ini->e[j].section, e->section) == 0)
                known_section = 1;
        if (known_section)
            return core_err_set(err, -1, "%s:%d: [%s] %s: unknown key", ini->path, e->line,
                                e->section, e->key);
        return core_err_set(err, -1, "%s:%d: [%s]: unknown section (key '%s')", ini->path,
                            e->line, e->section, e->key);
    }
    return 0;
}

int core_parse_range(const char *s, double *out, int nmax, int *count)
{
    double a[3];
    int k = 0;
    char buf[128];
    if (strlen(s) >= sizeof buf)
        return -1;
    strcpy(buf, s);
    char *rest = buf;
    for (char *tok; (tok = next_item(&rest, ':'));) {
        if (k == 3 || parse_double(tok, &a[k]))
            return -1;
        k++;
    }
    if (k == 1) {
        if (nmax < 1)
            return -1;
        out[0] = a[0];
        *count = 1;
        return 0;
    }
    if (k != 3 || a[2] <= 0.0 || a[1] < a[0])
        return -1;
    /* counted in double: a step tiny against the range gives a count past
     * INT_MAX (or infinite), which does not convert to an int */
    double span = floor((a[1] - a[0]) / a[2] + 1e-9) + 1.0;
    if (!(span <= nmax))
        return -1;
    int m = (int)span;
    for (int i = 0; i < m; i++)
        out[i] = a[0] + i * a[2];
    *count = m;
    return 0;
}

int core_parse_vec3(const char *s, double v[3], const char **end)
{
    char *e;
    for (int i = 0; i < 3; i++) {
        v[i] = strtod(s, &e);
        if (e == s || !isfinite(v[i]) || (i < 2 && *e != ','))
            return -1;
        s = e + 1;
    }
    if (end)
        *end = e;
    return end || !*e ? 0 : -1;
}
