/* soak_check.c -- what the flight loop's soak (bench/soak/soak.sh) did, read
 * back from what it left: the loop's LCM log and the airwake database.
 *
 *   soak_check --log RUN.lcm --sent SENT.json [--good ID] [--db DIR]
 *              [--json OUT.json] [--md OUT.md] [--extra KEY=VALUE]...
 *
 * The log: framed whole first (sim_log_check_frames, the check every
 * reader of disim's logs makes), then every event read with
 * lcm_eventlog_read_next_event; each message the loop published
 * (heli_state_t, ship_state_t, sim_status_t, run_info_t) must pass
 * disim_lcm_check_raw and decode. Each message the loop received (the log
 * holds every one, before the loop's checks) is put in its soak class
 * (bench/soak/soak.h) from its content: pilot_input_t by its station id
 * (the genuine station's by its seq: above the last by at most 10^6 is
 * genuine, at or below it a replay, further a jump ahead), sim_control_t
 * by the class in its seq (soak_tx), what does not decode by its
 * fingerprint. Each control's answer is the first sim_status_t naming its
 * seq. The loop's own counts are its last status's (STOPPED): each
 * station's taken and refused, the refusals from no readable station, the
 * controls refused, the overruns and the step times.
 *
 * Checked (each failure listed under "failures", exit 1):
 * - the log reads back whole, every published message decodes, the last
 *   status is STOPPED;
 * - no soak station's message was taken (soak-trunc, -nan, -huge, -flood
 *   and the intruders: refused, each counted), the genuine station's taken
 *   count is its genuine messages' and its refused count the replays' and
 *   jumps' that arrived;
 * - the refusals from no readable station are the random buffers and the
 *   intruders' take-overs that arrived;
 * - no bad control was accepted, and the controls refused are those that
 *   arrived less those accepted;
 * - the database (--db): every field's checksum (size and CRC-64 in its
 *   .sum) holds, every entry has both files, no temporary file is left,
 *   every queued and running request parses, and awdb_query finds each
 *   listed field READY. */
#include "awdb.h"
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wformat-truncation" /* paths and reasons cut to their fields on purpose */
#endif
#include "disim_lcm.h"
#include "sim.h"
#include "soak.h"

#include <dirent.h>
#include <lcm/eventlog.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* the loop's counts and the classes of what arrived */
typedef struct tally {
    double heli_gap[3]; /* soak_tx's heli_state_t gaps while running: p50, p99, max (ms) */
    long long heli_gap_n, heli_gap_over;
    long long sent[SOAK_NCLASS], arrived[SOAK_NCLASS], accepted[SOAK_NCLASS], refused_ans[SOAK_NCLASS];
    long long pilot_genuine, pilot_other, ctl_ios, ctl_ios_acc, ctl_ios_ref, ctl_undecoded, ctl_other;
    long long events, bytes, published, published_bad, statuses, heli, ship, run_info, other_ch;
    long long good_max_seq;
    double good_t_s;            /* run time of the last genuine message */
    long long spoof_after_silence; /* replays and jumps more than 0.5 s after it (the restart rule may take one) */
    /* what had arrived when the last status was sent (the loop's counts in it cover those) */
    long long snap_arrived[SOAK_NCLASS], snap_events, snap_genuine, snap_pilot_other, snap_ios;
    /* the longest application of each command (sim_status_t control_apply_s), s */
    double apply_max[DISIM_SIM_CONTROL_T_RESTORE + 1];
    /* the last status */
    int have_status, state;
    long long overruns, refused_unknown, control_refused;
    double p50, p99, max, sim_time_s, last_t_s;
    int nst;
    char st_id[SIM_PILOTS_MAX][SIM_STATION_ID_MAX];
    long long st_taken[SIM_PILOTS_MAX], st_refused[SIM_PILOTS_MAX], st_gaps[SIM_PILOTS_MAX];
    /* the step's maximum as it grew: when, and the last control answered before */
    int njumps;
    struct { double t_s, max_s, idle_s; int cmd; long long overruns; } jump[16];
    double idle_t_s; /* run time of the last status PAUSED or STOPPED (-1: none) */
    long long ov_window[64]; /* overruns at the end of each 5 min of run time */
    int nwin;
    int last_cmd;
    /* answers seen (seq), to count each once */
    long long *seen;
    size_t cap;
    FILE *timeline; /* --timeline: one row per status */
} tally;

static int seen_add(tally *t, long long seq)
{
    size_t h = (size_t)((uint64_t)seq * 0x9e3779b97f4a7c15ull >> 20) & (t->cap - 1);
    while (t->seen[h] != -1) {
        if (t->seen[h] == seq)
            return 0;
        h = (h + 1) & (t->cap - 1);
    }
    t->seen[h] = seq;
    return 1;
}

static int fingerprint_is(const unsigned char *b, int n, int64_t hash)
{
    if (n < 8)
        return 0;
    for (int i = 0; i < 8; i++)
        if (b[i] != (unsigned char)((uint64_t)hash >> (56 - 8 * i)))
            return 0;
    return 1;
}

static int id_is(const char *id, const char *prefix) { return !strncmp(id, prefix, strlen(prefix)); }

static void pilot_class(tally *t, const char *good, const unsigned char *b, int n, double t_s)
{
    if (disim_lcm_check_raw("pilot_input_t", b, n, NULL, 0) != 0) {
        /* a cut message of soak-trunc keeps its id; anything else is random */
        int trunc = fingerprint_is(b, n, __disim_pilot_input_t_get_hash()) && n >= 31 &&
                    !memcmp(b + 16, "\0\0\0\013soak-trunc", 14);
        t->arrived[trunc ? SOAK_PILOT_TRUNC : SOAK_PILOT_RANDOM]++;
        return;
    }
    disim_pilot_input_t m;
    memset(&m, 0, sizeof m);
    if (disim_pilot_input_t_decode(b, 0, n, &m) != n) {
        t->arrived[SOAK_PILOT_RANDOM]++;
        disim_pilot_input_t_decode_cleanup(&m);
        return;
    }
    if (!strcmp(m.station_id, good)) {
        if (m.seq > t->good_max_seq && m.seq - t->good_max_seq <= 1000000LL) {
            t->pilot_genuine++;
            t->good_max_seq = m.seq;
            t->good_t_s = t_s;
        } else {
            if (t_s - t->good_t_s > 0.5 + 1e-9)
                t->spoof_after_silence++;
            t->arrived[m.seq <= t->good_max_seq ? SOAK_PILOT_REPLAY : SOAK_PILOT_AHEAD]++;
        }
    } else if (!strcmp(m.station_id, "soak-trunc"))
        t->arrived[SOAK_PILOT_TRUNC]++;
    else if (!strcmp(m.station_id, "soak-nan"))
        t->arrived[SOAK_PILOT_NAN]++;
    else if (!strcmp(m.station_id, "soak-huge"))
        t->arrived[SOAK_PILOT_HUGE]++;
    else if (!strcmp(m.station_id, "soak-flood"))
        t->arrived[SOAK_PILOT_FLOOD]++;
    else if (id_is(m.station_id, "intruder-"))
        t->arrived[SOAK_PILOT_TAKEOVER]++;
    else
        t->pilot_other++;
    disim_pilot_input_t_decode_cleanup(&m);
}

static void ctl_class(tally *t, const unsigned char *b, int n)
{
    disim_sim_control_t m;
    memset(&m, 0, sizeof m);
    if (disim_lcm_check_raw("sim_control_t", b, n, NULL, 0) != 0 || disim_sim_control_t_decode(b, 0, n, &m) != n) {
        t->ctl_undecoded++; /* random or cut: told apart by the fingerprint where there are 8 bytes */
        t->arrived[fingerprint_is(b, n, __disim_sim_control_t_get_hash()) ? SOAK_CTL_TRUNC : SOAK_CTL_RANDOM]++;
    } else {
        int c = soak_seq_class(m.seq);
        if (c >= 0)
            t->arrived[c]++;
        else if (m.seq < 0)
            t->arrived[SOAK_CTL_BAD]++; /* the bad cycle's negative seq */
        else
            t->ctl_ios++;
    }
    disim_sim_control_t_decode_cleanup(&m);
}

static void take_status(tally *t, const disim_sim_status_t *m, double t_s)
{
    t->statuses++;
    if (m->control_seq >= 0 && m->control_result != DISIM_SIM_STATUS_T_CONTROL_NONE && seen_add(t, m->control_seq)) {
        int c = soak_seq_class(m->control_seq), acc = m->control_result == DISIM_SIM_STATUS_T_CONTROL_ACCEPTED;
        if (c >= 0)
            (acc ? t->accepted : t->refused_ans)[c]++;
        else if (acc)
            t->ctl_ios_acc++;
        else
            t->ctl_ios_ref++;
        t->last_cmd = m->control_command;
    }
    if (m->step_max_s > t->max + 1e-4 && t->njumps < 16 && t->have_status) {
        t->jump[t->njumps].t_s = t_s;
        t->jump[t->njumps].max_s = m->step_max_s;
        t->jump[t->njumps].cmd = t->last_cmd;
        t->jump[t->njumps].overruns = m->overruns;
        /* a pause or a crash's wait just before: the pacer counts the wait in the step */
        t->jump[t->njumps].idle_s = t->idle_t_s;
        t->njumps++;
    }
    int w = (int)(t_s / 300.0);
    if (w >= 0 && w < 64) {
        t->ov_window[w] = m->overruns;
        if (w + 1 > t->nwin)
            t->nwin = w + 1;
    }
    if (t->timeline)
        fprintf(t->timeline, "%.3f,%.3f,%d,%lld,%.0f,%.0f,%lld,%d,%d\n", t_s, m->sim_time_s, m->state, (long long)m->overruns,
                1e6 * m->step_p99_s, 1e6 * m->step_max_s, (long long)m->control_seq, m->control_command, m->flags);
    memcpy(t->snap_arrived, t->arrived, sizeof t->arrived);
    t->snap_genuine = t->pilot_genuine;
    t->snap_events = t->events;
    t->snap_pilot_other = t->pilot_other;
    t->snap_ios = t->ctl_ios;
    if (m->control_command >= 1 && m->control_command <= DISIM_SIM_CONTROL_T_RESTORE &&
        m->control_apply_s > t->apply_max[m->control_command])
        t->apply_max[m->control_command] = m->control_apply_s;
    if (m->state != DISIM_SIM_STATUS_T_RUNNING)
        t->idle_t_s = t_s;
    t->have_status = 1;
    t->state = m->state;
    t->overruns = m->overruns;
    t->refused_unknown = m->refused_unknown;
    t->control_refused = m->control_refused;
    t->p50 = m->step_p50_s, t->p99 = m->step_p99_s, t->max = m->step_max_s;
    t->sim_time_s = m->sim_time_s;
    t->nst = m->n_stations < SIM_PILOTS_MAX ? m->n_stations : SIM_PILOTS_MAX;
    for (int i = 0; i < t->nst; i++) {
        snprintf(t->st_id[i], sizeof t->st_id[i], "%s", m->station_ids[i]);
        t->st_taken[i] = m->station_received[i];
        t->st_refused[i] = m->station_refused[i];
        t->st_gaps[i] = m->station_gaps[i];
    }
}

#define PUBLISHED(T)                                                                                                \
    do {                                                                                                            \
        disim_##T m;                                                                                                \
        memset(&m, 0, sizeof m);                                                                                    \
        ok = disim_lcm_check_raw(#T, ev->data, ev->datalen, NULL, 0) == 0 &&                                        \
             disim_##T##_decode(ev->data, 0, ev->datalen, &m) == ev->datalen;                                       \
        disim_##T##_decode_cleanup(&m);                                                                             \
    } while (0)

static int read_log(tally *t, const char *path, const char *good, char *fail, size_t nf)
{
    core_err err = {0};
    sim_log_frames fr;
    if (sim_log_check_frames(path, &fr, &err) != 0) {
        snprintf(fail, nf, "the log does not frame: %.200s", err.msg);
        return -1;
    }
    lcm_eventlog_t *el = lcm_eventlog_create(path, "r");
    if (!el) {
        snprintf(fail, nf, "%.300s: lcm_eventlog_create failed", path);
        return -1;
    }
    lcm_eventlog_event_t *ev;
    while ((ev = lcm_eventlog_read_next_event(el))) {
        t->events++;
        t->bytes += ev->datalen;
        double t_s = 1e-6 * (double)ev->timestamp;
        t->last_t_s = t_s;
        const unsigned char *b = ev->data;
        int ok = 1;
        if (!strcmp(ev->channel, DISIM_CH_PILOT_INPUT))
            pilot_class(t, good, b, ev->datalen, t_s);
        else if (!strcmp(ev->channel, DISIM_CH_SIM_CONTROL))
            ctl_class(t, b, ev->datalen);
        else if (!strcmp(ev->channel, DISIM_CH_SIM_STATUS)) {
            disim_sim_status_t m;
            memset(&m, 0, sizeof m);
            ok = disim_lcm_check_raw("sim_status_t", b, ev->datalen, NULL, 0) == 0 &&
                 disim_sim_status_t_decode(b, 0, ev->datalen, &m) == ev->datalen;
            if (ok)
                take_status(t, &m, t_s);
            disim_sim_status_t_decode_cleanup(&m);
            t->published++;
        } else if (!strcmp(ev->channel, DISIM_CH_HELI_STATE)) {
            PUBLISHED(heli_state_t);
            t->published++, t->heli++;
        } else if (!strcmp(ev->channel, DISIM_CH_SHIP_STATE)) {
            PUBLISHED(ship_state_t);
            t->published++, t->ship++;
        } else if (!strcmp(ev->channel, DISIM_CH_RUN_INFO)) {
            PUBLISHED(run_info_t);
            t->published++, t->run_info++;
        } else
            t->other_ch++;
        if (!ok)
            t->published_bad++;
        lcm_eventlog_free_event(ev);
    }
    lcm_eventlog_destroy(el);
    if (t->events != fr.n_events) {
        snprintf(fail, nf, "the log frames %ld events, lcm_eventlog_read_next_event read %lld", fr.n_events, t->events);
        return -1;
    }
    return 0;
}

/* ---- the database */
typedef struct dbcheck {
    int fields, fields_ok, crc_bad, torn, temps, req, req_bad, failed, listed, ready;
    char first_bad[300];
} dbcheck;

static void db_bad(dbcheck *d, const char *fmt, const char *a, const char *b)
{
    if (!d->first_bad[0])
        snprintf(d->first_bad, sizeof d->first_bad, fmt, a, b);
}

static int ends(const char *s, const char *suf)
{
    size_t n = strlen(s), k = strlen(suf);
    return n >= k && !strcmp(s + n - k, suf);
}

static void db_field(dbcheck *d, const char *dir, const char *name)
{
    char sum[4200], h5[4200];
    snprintf(sum, sizeof sum, "%.3800s/fields/%.255s", dir, name);
    snprintf(h5, sizeof h5, "%.3800s/fields/%.*s.h5", dir, (int)(strlen(name) - 4), name);
    d->fields++;
    core_err err = {0};
    core_ini *ini = core_ini_load(sum, &err);
    const core_ini_entry *s = ini ? core_ini_find(ini, "field", "size") : NULL;
    const core_ini_entry *c = ini ? core_ini_find(ini, "field", "crc64") : NULL;
    uint64_t crc = 0, size = 0;
    if (!s || !c) {
        d->crc_bad++;
        db_bad(d, "%s: %s", sum, ini ? "no [field] size and crc64" : err.msg);
    } else if (awdb_file_crc64(h5, &crc, &size, &err) != 0) {
        d->torn++;
        db_bad(d, "%s: %s", h5, err.msg);
    } else if (strtoull(c->value, NULL, 16) != crc || strtoull(s->value, NULL, 10) != size) {
        d->crc_bad++;
        db_bad(d, "%s: %s", h5, "size or CRC-64 not the .sum's");
    } else
        d->fields_ok++;
    core_ini_destroy(ini);
}

static int list_key(void *user, const awdb_key *key)
{
    awdb *db = ((void **)user)[0];
    dbcheck *d = ((void **)user)[1];
    awdb_key k = *key;
    d->listed++;
    if (awdb_query(db, &k, NULL, 0) == AWDB_READY)
        d->ready++;
    else {
        char name[AWDB_NAME_MAX];
        awdb_key_name(key, name, sizeof name);
        db_bad(d, "%s: %s", name, "listed but not READY");
    }
    return 0;
}

static int check_db(const char *dir, dbcheck *d, char *fail, size_t nf)
{
    static const char *sub[] = {"fields", "queue", "running", "failed", "waiting", "."};
    for (size_t i = 0; i < sizeof sub / sizeof sub[0]; i++) {
        char p[4200];
        snprintf(p, sizeof p, "%.3800s/%s", dir, sub[i]);
        DIR *D = opendir(p);
        if (!D) {
            if (i == 0) {
                snprintf(fail, nf, "%.300s: cannot read", p);
                return -1;
            }
            continue;
        }
        struct dirent *e;
        while ((e = readdir(D))) {
            const char *n = e->d_name;
            if (n[0] == '.' && (!n[1] || (n[1] == '.' && !n[2])))
                continue;
            if (strstr(n, ".tmp") || ends(n, ".part")) {
                d->temps++;
                db_bad(d, "%s/%s: a temporary file left", p, n);
            } else if (i == 0 && ends(n, ".sum"))
                db_field(d, dir, n);
            else if (i == 0 && ends(n, ".h5")) {
                char s[4200];
                snprintf(s, sizeof s, "%.3800s/%.*s.sum", p, (int)(strlen(n) - 3), n);
                FILE *f = fopen(s, "r");
                if (f)
                    fclose(f);
                else {
                    d->torn++;
                    db_bad(d, "%s/%s: no .sum beside it", p, n);
                }
            } else if ((i == 1 || i == 2) && ends(n, ".req")) {
                char r[4200];
                snprintf(r, sizeof r, "%.3800s/%.255s", p, n);
                core_err err = {0};
                core_ini *ini = core_ini_load(r, &err);
                d->req++;
                if (!ini || core_ini_count(ini) == 0) {
                    d->req_bad++;
                    db_bad(d, "%s: %s", r, ini ? "empty" : err.msg);
                }
                core_ini_destroy(ini);
            } else if (i == 3)
                d->failed++;
        }
        closedir(D);
    }
    core_err err = {0};
    awdb *db = awdb_open(dir, NULL, &err);
    if (!db) {
        snprintf(fail, nf, "awdb_open: %.200s", err.msg);
        return -1;
    }
    void *u[2] = {db, d};
    if (awdb_list(db, list_key, u, &err) < 0)
        db_bad(d, "awdb_list: %s%s", err.msg, "");
    awdb_close(db);
    return 0;
}

/* ---- soak_tx's counts: lines "name": N of its JSON */
static int read_sent(tally *t, const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    char line[256];
    while (fgets(line, sizeof line, f)) {
        char name[64];
        long long v;
        double x;
        if (sscanf(line, " \"%63[^\"]\": %lf", name, &x) == 2) {
            if (!strcmp(name, "heli_gap_p50_ms")) t->heli_gap[0] = x;
            if (!strcmp(name, "heli_gap_p99_ms")) t->heli_gap[1] = x;
            if (!strcmp(name, "heli_gap_max_ms")) t->heli_gap[2] = x;
            if (!strcmp(name, "heli_gap_running_n")) t->heli_gap_n = (long long)x;
            if (!strcmp(name, "heli_gaps_over_100ms")) t->heli_gap_over = (long long)x;
        }
        if (sscanf(line, " \"%63[^\"]\": %lld", name, &v) == 2)
            for (int c = 0; c < SOAK_NCLASS; c++)
                if (!strcmp(name, soak_class_name[c]))
                    t->sent[c] = v;
    }
    fclose(f);
    return 0;
}

static int station(const tally *t, const char *id)
{
    for (int i = 0; i < t->nst; i++)
        if (!strcmp(t->st_id[i], id))
            return i;
    return -1;
}

#define NFAIL 32
typedef struct fails {
    int n;
    char f[NFAIL][300];
} fails;

static void failf(fails *F, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void failf(fails *F, const char *fmt, ...)
{
    if (F->n >= NFAIL)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(F->f[F->n++], sizeof F->f[0], fmt, ap);
    va_end(ap);
}

/* The loop's refusals against what arrived, per bucket. */
static void judge(const tally *t, const char *good, fails *F)
{
    static const struct { const char *id; int cls; } soak_st[] = {
        {"soak-trunc", SOAK_PILOT_TRUNC}, {"soak-nan", SOAK_PILOT_NAN},
        {"soak-huge", SOAK_PILOT_HUGE}, {"soak-flood", SOAK_PILOT_FLOOD}};
    if (!t->have_status || t->state != DISIM_SIM_STATUS_T_STOPPED)
        failf(F, "the log's last status is not STOPPED (the loop did not finish)");
    if (t->published_bad)
        failf(F, "%lld messages the loop published do not decode", t->published_bad);
    for (size_t k = 0; k < 4; k++) {
        int i = station(t, soak_st[k].id);
        long long arr = t->snap_arrived[soak_st[k].cls];
        if (i < 0 && arr > 0)
            failf(F, "station %s: %lld arrived, not in the loop's status", soak_st[k].id, arr);
        else if (i >= 0 && (t->st_taken[i] != 0 || t->st_refused[i] != arr))
            failf(F, "station %s: %lld arrived, the loop took %lld and refused %lld", soak_st[k].id, arr,
                  t->st_taken[i], t->st_refused[i]);
    }
    int g = station(t, good);
    long long spoof = t->snap_arrived[SOAK_PILOT_REPLAY] + t->snap_arrived[SOAK_PILOT_AHEAD];
    if (g < 0)
        failf(F, "the genuine station %s is not in the loop's status", good);
    else if (t->st_taken[g] != t->snap_genuine || t->st_refused[g] != spoof)
        failf(F, "station %s: %lld genuine and %lld replayed or ahead arrived; the loop took %lld, refused %lld", good,
              t->snap_genuine, spoof, t->st_taken[g], t->st_refused[g]);
    long long unk = t->snap_arrived[SOAK_PILOT_RANDOM] + t->snap_arrived[SOAK_PILOT_TAKEOVER] + t->snap_pilot_other;
    if (t->refused_unknown != unk)
        failf(F, "%lld random, take-over and other buffers arrived, the loop refused %lld from no readable station",
              unk, t->refused_unknown);
    long long ctl_arr = t->snap_ios, ctl_acc = t->ctl_ios_acc;
    for (int c = SOAK_CTL_RANDOM; c <= SOAK_CTL_BURST; c++)
        ctl_arr += t->snap_arrived[c], ctl_acc += t->accepted[c];
    if (t->control_refused != ctl_arr - ctl_acc)
        failf(F, "%lld controls arrived and %lld were accepted, the loop counts %lld refused (expected %lld)", ctl_arr,
              ctl_acc, t->control_refused, ctl_arr - ctl_acc);
    for (int c = SOAK_CTL_RANDOM; c <= SOAK_CTL_BAD; c++)
        if (t->accepted[c])
            failf(F, "%s: %lld accepted", soak_class_name[c], t->accepted[c]);
}

static void write_json(FILE *f, const tally *t, const char *good, const dbcheck *d, int have_db, const fails *F,
                       char **extra, int nextra)
{
    fprintf(f, "{\n  \"log\": {\"events\": %lld, \"bytes\": %lld, \"run_s\": %.1f, \"published\": %lld, "
               "\"published_bad\": %lld, \"statuses\": %lld, \"heli_state\": %lld, \"ship_state\": %lld, "
               "\"run_info\": %lld, \"other_channels\": %lld},\n",
            t->events, t->bytes, t->last_t_s, t->published, t->published_bad, t->statuses, t->heli, t->ship,
            t->run_info, t->other_ch);
    fprintf(f, "  \"loop\": {\"state\": %d, \"overruns\": %lld, \"step_p50_us\": %.0f, \"step_p99_us\": %.0f, "
               "\"step_max_us\": %.0f, \"refused_unknown\": %lld, \"control_refused\": %lld, \"stations\": {",
            t->state, t->overruns, 1e6 * t->p50, 1e6 * t->p99, 1e6 * t->max, t->refused_unknown, t->control_refused);
    for (int i = 0; i < t->nst; i++)
        fprintf(f, "%s\"%s\": {\"taken\": %lld, \"refused\": %lld, \"missing\": %lld}", i ? ", " : "", t->st_id[i],
                t->st_taken[i], t->st_refused[i], t->st_gaps[i]);
    long long late = t->events - t->snap_events;
    fprintf(f, "}},\n  \"events_after_last_status\": %lld,\n  \"genuine\": {\"station\": \"%s\", \"arrived\": %lld},\n  \"classes\": {", late, good,
            t->snap_genuine);
    for (int c = 0; c < SOAK_NCLASS; c++)
        fprintf(f, "%s\n    \"%s\": {\"sent\": %lld, \"arrived\": %lld, \"answered_accepted\": %lld, "
                   "\"answered_refused\": %lld}",
                c ? "," : "", soak_class_name[c], t->sent[c], t->snap_arrived[c], t->accepted[c], t->refused_ans[c]);
    fprintf(f, "\n  },\n  \"ios\": {\"arrived\": %lld, \"accepted\": %lld, \"refused\": %lld},\n", t->snap_ios,
            t->ctl_ios_acc, t->ctl_ios_ref);
    fprintf(f, "  \"genuine_spoofs_after_silence\": %lld,\n", t->spoof_after_silence);
    fprintf(f, "  \"heli_state_gaps_running\": {\"n\": %lld, \"p50_ms\": %.0f, \"p99_ms\": %.0f, \"max_ms\": %.1f, "
               "\"over_100ms\": %lld},\n",
            t->heli_gap_n, t->heli_gap[0], t->heli_gap[1], t->heli_gap[2], t->heli_gap_over);
    fprintf(f, "  \"step_max_growth\": [");
    for (int i = 0; i < t->njumps; i++)
        fprintf(f, "%s{\"run_s\": %.1f, \"max_us\": %.0f, \"last_control\": %d, \"last_paused_or_stopped_run_s\": %.1f, \"overruns\": %lld}",
                i ? ", " : "", t->jump[i].t_s, 1e6 * t->jump[i].max_s, t->jump[i].cmd, t->jump[i].idle_s,
                t->jump[i].overruns);
    fprintf(f, "],\n  \"control_apply_max_ms\": {");
    static const char *cname[] = {"", "pause", "resume", "reset", "load", "reset_hover", "reset_deck", "reposition",
                                  "set_wod", "set_sea", "set_turbulence", "snapshot", "restore"};
    for (int c = 1; c <= DISIM_SIM_CONTROL_T_RESTORE; c++)
        fprintf(f, "%s\"%s\": %.1f", c > 1 ? ", " : "", cname[c], 1e3 * t->apply_max[c]);
    fprintf(f, "},\n  \"overruns_by_5min\": [");
    for (int i = 0; i < t->nwin; i++)
        fprintf(f, "%s%lld", i ? ", " : "", t->ov_window[i]);
    fprintf(f, "],\n");
    if (have_db)
        fprintf(f, "  \"db\": {\"fields\": %d, \"fields_ok\": %d, \"crc_bad\": %d, \"torn\": %d, \"temporaries\": %d, "
                   "\"requests\": %d, \"requests_bad\": %d, \"failed\": %d, \"listed\": %d, \"ready\": %d, "
                   "\"first_problem\": \"%s\"},\n",
                d->fields, d->fields_ok, d->crc_bad, d->torn, d->temps, d->req, d->req_bad, d->failed, d->listed,
                d->ready, d->first_bad);
    for (int i = 0; i < nextra; i++) {
        char *eq = strchr(extra[i], '=');
        if (eq)
            fprintf(f, "  \"%.*s\": \"%s\",\n", (int)(eq - extra[i]), extra[i], eq + 1);
    }
    fprintf(f, "  \"failures\": [");
    for (int i = 0; i < F->n; i++)
        fprintf(f, "%s\n    \"%s\"", i ? "," : "", F->f[i]);
    fprintf(f, "%s],\n  \"passed\": %s\n}\n", F->n ? "\n  " : "", F->n ? "false" : "true");
}

static void write_md(FILE *f, const tally *t, const char *good, const dbcheck *d, int have_db, const fails *F)
{
    int g = station(t, good);
    fprintf(f, "| class | sent | arrived (log) | taken by the loop | refused by the loop |\n|---|---:|---:|---:|---:|\n");
    fprintf(f, "| genuine station (%s) | | %lld | %lld | %lld (the replays and jumps below) |\n", good, t->snap_genuine,
            g >= 0 ? t->st_taken[g] : -1, g >= 0 ? t->st_refused[g] : -1);
    static const char *stid[SOAK_NCLASS] = {[SOAK_PILOT_TRUNC] = "soak-trunc", [SOAK_PILOT_NAN] = "soak-nan",
                                            [SOAK_PILOT_HUGE] = "soak-huge", [SOAK_PILOT_FLOOD] = "soak-flood"};
    for (int c = 0; c <= SOAK_PILOT_FLOOD; c++) {
        int i = stid[c] ? station(t, stid[c]) : -1;
        if (i >= 0)
            fprintf(f, "| %s | %lld | %lld | %lld | %lld |\n", soak_class_name[c], t->sent[c], t->snap_arrived[c],
                    t->st_taken[i], t->st_refused[i]);
        else
            fprintf(f, "| %s | %lld | %lld | 0 | %s |\n", soak_class_name[c], t->sent[c], t->snap_arrived[c],
                    c == SOAK_PILOT_REPLAY || c == SOAK_PILOT_AHEAD ? "in the genuine station's" : "from no readable station");
    }
    fprintf(f, "| (from no readable station, all) | | %lld | | %lld |\n",
            t->snap_arrived[SOAK_PILOT_RANDOM] + t->snap_arrived[SOAK_PILOT_TAKEOVER] + t->snap_pilot_other, t->refused_unknown);
    fprintf(f, "\n| control class | sent | arrived (log) | answered accepted | answered refused |\n|---|---:|---:|---:|---:|\n");
    fprintf(f, "| ctl_random and ctl_trunc (not decoded: answered with seq -1) | %lld | %lld | | |\n",
            t->sent[SOAK_CTL_RANDOM] + t->sent[SOAK_CTL_TRUNC], t->snap_arrived[SOAK_CTL_RANDOM] + t->snap_arrived[SOAK_CTL_TRUNC]);
    for (int c = SOAK_CTL_BAD; c <= SOAK_CTL_BURST; c++)
        fprintf(f, "| %s | %lld | %lld | %lld | %lld |\n", soak_class_name[c], t->sent[c], t->snap_arrived[c], t->accepted[c],
                t->refused_ans[c]);
    fprintf(f, "| disim ios | | %lld | %lld | %lld |\n", t->snap_ios, t->ctl_ios_acc, t->ctl_ios_ref);
    fprintf(f, "| (all: the loop's count of refused) | | | | %lld |\n", t->control_refused);
    fprintf(f, "\nOther processes' channels (not the loop's): heli_garbage %lld, status_garbage %lld, awreq_garbage "
               "%lld sent.\n",
            t->sent[SOAK_HELI_GARBAGE], t->sent[SOAK_STATUS_GARBAGE], t->sent[SOAK_AWREQ_GARBAGE]);
    fprintf(f, "\nThe longest application of a control (ms): reset %.1f, load %.1f, reset hover %.1f, reset deck %.1f, "
               "reposition %.1f, set wod %.1f, set sea %.1f, restore %.1f.\n",
            1e3 * t->apply_max[3], 1e3 * t->apply_max[4], 1e3 * t->apply_max[5], 1e3 * t->apply_max[6],
            1e3 * t->apply_max[7], 1e3 * t->apply_max[8], 1e3 * t->apply_max[9], 1e3 * t->apply_max[12]);
    fprintf(f, "\nThe loop: step p50 %.0f us, p99 %.0f us, max %.0f us; %lld overruns; %.0f s of run time logged; "
               "log %lld events, %.1f MB, read back whole.\n",
            1e6 * t->p50, 1e6 * t->p99, 1e6 * t->max, t->overruns, t->last_t_s, t->events, 1e-6 * (double)t->bytes);
    fprintf(f, "\nFrom outside (soak_tx): the wall time between two heli_state_t (50 Hz) while the loop ran, "
               "%lld gaps: p50 %.0f ms, p99 %.0f ms, max %.1f ms, %lld over 100 ms.\n",
            t->heli_gap_n, t->heli_gap[0], t->heli_gap[1], t->heli_gap[2], t->heli_gap_over);
    if (have_db)
        fprintf(f, "\nThe database: %d fields, %d with their checksum holding, %d torn, %d CRC mismatches, %d "
                   "temporaries left, %d requests (%d unreadable), %d failed builds, %d listed / %d READY.\n",
                d->fields, d->fields_ok, d->torn, d->crc_bad, d->temps, d->req, d->req_bad, d->failed, d->listed,
                d->ready);
    fprintf(f, "\n%s\n", F->n ? "FAILED:" : "Passed: every check held.");
    for (int i = 0; i < F->n; i++)
        fprintf(f, "- %s\n", F->f[i]);
}

int main(int argc, char **argv)
{
    const char *log = NULL, *sent = NULL, *good = "soak-good", *dbdir = NULL, *json = NULL, *md = NULL, *timeline = NULL;
    char *extra[32];
    int nextra = 0;
    for (int i = 1; i + 1 < argc; i += 2) {
        const char *a = argv[i], *v = argv[i + 1];
        if (!strcmp(a, "--log")) log = v;
        else if (!strcmp(a, "--sent")) sent = v;
        else if (!strcmp(a, "--good")) good = v;
        else if (!strcmp(a, "--db")) dbdir = v;
        else if (!strcmp(a, "--json")) json = v;
        else if (!strcmp(a, "--md")) md = v;
        else if (!strcmp(a, "--extra") && nextra < 32) extra[nextra++] = argv[i + 1];
        else if (!strcmp(a, "--timeline")) timeline = v;
        else
            log = NULL, i = argc;
    }
    if (!log || (argc % 2) == 0) {
        fprintf(stderr, "usage: soak_check --log RUN.lcm [--sent SENT.json] [--good ID] [--db DIR] [--json OUT] "
                        "[--md OUT] [--timeline OUT.csv] [--extra KEY=VALUE]...\n");
        return 2;
    }
    static tally t;
    t.good_max_seq = -1;
    t.idle_t_s = -1.0;
    t.cap = 1 << 22;
    t.seen = malloc(t.cap * sizeof *t.seen);
    if (!t.seen)
        return 1;
    memset(t.seen, 0xff, t.cap * sizeof *t.seen);
    fails F = {0};
    if (timeline && (t.timeline = fopen(timeline, "w")))
        fprintf(t.timeline, "run_s,sim_time_s,state,overruns,step_p99_us,step_max_us,control_seq,control_command,flags\n");
    if (sent && read_sent(&t, sent) != 0)
        failf(&F, "%s: cannot read soak_tx's counts", sent);
    char fail[400] = "";
    if (read_log(&t, log, good, fail, sizeof fail) != 0)
        failf(&F, "%s", fail);
    if (t.timeline)
        fclose(t.timeline);
    judge(&t, good, &F);
    dbcheck d = {0};
    if (dbdir) {
        fail[0] = '\0';
        if (check_db(dbdir, &d, fail, sizeof fail) != 0)
            failf(&F, "%s", fail);
        if (d.crc_bad || d.torn || d.temps || d.req_bad || d.ready != d.listed || d.fields_ok != d.fields)
            failf(&F, "the database: %.250s", d.first_bad);
    }
    FILE *f = json ? fopen(json, "w") : stdout;
    if (f) {
        write_json(f, &t, good, &d, dbdir != NULL, &F, extra, nextra);
        if (f != stdout)
            fclose(f);
    }
    if (md && (f = fopen(md, "w"))) {
        write_md(f, &t, good, &d, dbdir != NULL, &F);
        fclose(f);
    }
    free(t.seen);
    return F.n ? 1 : 0;
}
