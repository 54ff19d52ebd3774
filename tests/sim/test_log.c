/* test_log.c -- the LCM log of a run as a writer and reader pair (sim/log.c).
 *
 * 1. The writer's bytes are lcm_eventlog_write_event's: the same events
 *    (run_info_t, sim_status_t, heli_state_t and ship_state_t of ten
 *    states, pilot_input_t) written by both are the same file.
 * 2. Nothing is at the path before the commit, and only the temporary
 *    file beside it; after the commit the log and no temporary file.
 * 3. Read back (sim_log_load): the events, states, ship states and the
 *    one station's inputs counted, the states' times and positions as
 *    written (exactly at a sample), the run information as written, the
 *    SAS engaged as the status's flags say (FLAG_SAS, FLAG_SAS_OFF, and
 *    unknown for a status with neither, a log of an older disim).
 * 4. The committed log truncated (its last 10 bytes cut) and corrupted
 *    (the third event's sync word overwritten) is refused with an error
 *    naming the file, the event and what is wrong.
 * 5. A writer destroyed before its commit leaves nothing in the folder.
 * 6. Errors: a writer in a missing folder names the path; a commit that
 *    cannot rename (a folder at the path) names the path, says nothing
 *    was written and leaves no temporary file; a bad event (no channel)
 *    and a write after the commit are refused.
 * 7. Hostile files: an event whose data length is 0x7FFFFFFF (refused by
 *    its frame, before LCM's reader allocates it; the sizes said without
 *    an int overflow), /dev/zero and a folder (refused unread), a
 *    heli_state_t whose quaternion has infinities (refused, as the
 *    renderer refuses such a pose). */
#include "check.h"
#include "disim_lcm.h"
#include "sim.h"

#include <dirent.h>
#include <lcm/eventlog.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <errno.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#define NSTATES 10
#define MAXEV 32

typedef struct event {
    const char *ch;
    int64_t ts;
    int n;
    unsigned char buf[1024];
} event;

/* The events of a short run: its run_info_t, a status, ten states 20 ms
 * apart (the helicopter sinking 0.1 m a state), an input of one station
 * after the third. */
static int make_events(event *ev, int32_t status_flags)
{
    int n = 0;
    disim_run_info_t ri;
    memset(&ri, 0, sizeof ri);
    ri.scenario_path = (char *)"scenarios/cg47_uh60a.ini";
    ri.scenario = (char *)"cg47_uh60a";
    ri.aircraft_path = (char *)"scenarios/aircraft/uh60a.ini";
    ri.ship_path = (char *)"scenarios/ships/cg47.ini";
    ri.seed = 7;
    ri.sea_state = 3;
    ri.rate_hz = 200.0;
    ri.state_rate_hz = 50.0;
    ev[n] = (event){DISIM_CH_RUN_INFO, 0, 0, {0}};
    ev[n].n = disim_run_info_t_encode(ev[n].buf, 0, sizeof ev[n].buf, &ri);
    n++;
    disim_sim_status_t st;
    memset(&st, 0, sizeof st);
    st.state = DISIM_SIM_STATUS_T_RUNNING;
    st.active_station = -1;
    st.message = (char *)"";
    st.control_message = (char *)"";
    st.scenario = (char *)"cg47_uh60a";
    st.flags = status_flags;
    ev[n] = (event){DISIM_CH_SIM_STATUS, 0, 0, {0}};
    ev[n].n = disim_sim_status_t_encode(ev[n].buf, 0, sizeof ev[n].buf, &st);
    n++;
    for (int k = 0; k < NSTATES; k++) {
        int64_t ut = 20000 * (int64_t)k;
        disim_heli_state_t h;
        memset(&h, 0, sizeof h);
        h.utime = ut;
        h.seq = k;
        h.pos_S_m[0] = 1.0;
        h.pos_S_m[2] = -6.0 + 0.1 * k;
        h.pos_E_m[0] = 1.0;
        h.pos_E_m[2] = -6.0 + 0.1 * k;
        h.vel_E_mps[2] = 5.0;
        h.quat_EB[0] = 1.0;
        h.collective_pct = h.long_cyclic_pct = h.lat_cyclic_pct = h.pedal_pct = 50.0;
        ev[n] = (event){DISIM_CH_HELI_STATE, ut, 0, {0}};
        ev[n].n = disim_heli_state_t_encode(ev[n].buf, 0, sizeof ev[n].buf, &h);
        n++;
        disim_ship_state_t s;
        memset(&s, 0, sizeof s);
        s.utime = ut;
        s.seq = k;
        s.quat_ES[0] = 1.0;
        ev[n] = (event){DISIM_CH_SHIP_STATE, ut, 0, {0}};
        ev[n].n = disim_ship_state_t_encode(ev[n].buf, 0, sizeof ev[n].buf, &s);
        n++;
        if (k == 2) {
            disim_pilot_input_t in;
            memset(&in, 0, sizeof in);
            in.utime = ut;
            in.station_id = (char *)"seat1";
            in.collective_pct = in.long_cyclic_pct = in.lat_cyclic_pct = in.pedal_pct = 55.0;
            ev[n] = (event){DISIM_CH_PILOT_INPUT, ut, 0, {0}};
            ev[n].n = disim_pilot_input_t_encode(ev[n].buf, 0, sizeof ev[n].buf, &in);
            n++;
        }
    }
    return n;
}

static long file_size(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 ? (long)st.st_size : -1;
}

static unsigned char *read_all(const char *path, long *n)
{
    *n = file_size(path);
    FILE *f = fopen(path, "rb");
    unsigned char *b = *n > 0 && f ? malloc((size_t)*n) : NULL;
    if (b && fread(b, 1, (size_t)*n, f) != (size_t)*n) {
        free(b);
        b = NULL;
    }
    if (f)
        fclose(f);
    return b;
}

static void write_all(const char *path, const unsigned char *b, long n)
{
    FILE *f = fopen(path, "wb");
    if (f) {
        CHECK(fwrite(b, 1, (size_t)n, f) == (size_t)n);
        fclose(f);
    }
}

/* The entries of dir (not . and ..); the first one's name into first. */
static int entries(const char *dir, char *first, size_t nfirst)
{
    DIR *d = opendir(dir);
    int n = 0;
    if (first)
        first[0] = '\0';
    if (!d)
        return -1;
    for (struct dirent *e; (e = readdir(d));) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        if (n++ == 0 && first)
            snprintf(first, nfirst, "%s", e->d_name);
    }
    closedir(d);
    return n;
}

/* ---- 1., 2.: the writer's bytes and its commit */
static void test_write(const char *dir, const char *path, const event *ev, int nev)
{
    char ref[256], tmpname[256];
    snprintf(ref, sizeof ref, "%s.ref", path);
    lcm_eventlog_t *el = lcm_eventlog_create(ref, "w");
    CHECK(el != NULL);
    for (int i = 0; el && i < nev; i++) {
        lcm_eventlog_event_t e;
        memset(&e, 0, sizeof e);
        e.timestamp = ev[i].ts;
        e.channellen = (int32_t)strlen(ev[i].ch);
        e.datalen = ev[i].n;
        e.channel = (char *)ev[i].ch;
        e.data = (void *)ev[i].buf;
        CHECK(lcm_eventlog_write_event(el, &e) == 0);
    }
    if (el)
        lcm_eventlog_destroy(el);

    core_err err = {0};
    sim_log_writer *w = sim_log_writer_create(path, &err);
    CHECK(w != NULL);
    if (!w) {
        fprintf(stderr, "writer: %s\n", err.msg);
        unlink(ref);
        return;
    }
    for (int i = 0; i < nev; i++)
        CHECK(sim_log_writer_write(w, ev[i].ch, ev[i].ts, ev[i].buf, ev[i].n, &err) == 0);
    CHECK(sim_log_writer_events(w) == nev);
    /* before the commit: no log, one temporary file beside it (and the reference) */
    CHECK(file_size(path) < 0);
    int n = 0;
    DIR *d = opendir(dir);
    for (struct dirent *e; d && (e = readdir(d));)
        if (strstr(e->d_name, ".tmp")) {
            n++;
            snprintf(tmpname, sizeof tmpname, "%s", e->d_name);
        }
    if (d)
        closedir(d);
    printf("before the commit: %d temporary file(s), %s\n", n, n ? tmpname : "-");
    CHECK(n == 1 && !strncmp(tmpname, "run.log.tmp", 11));
    CHECK(sim_log_writer_commit(w, &err) == 0);
    /* closed: further writes and commits are refused */
    core_err e2 = {0};
    CHECK(sim_log_writer_write(w, DISIM_CH_HELI_STATE, 0, ev[0].buf, ev[0].n, &e2) < 0 && strstr(e2.msg, path));
    CHECK(sim_log_writer_commit(w, &e2) < 0);
    sim_log_writer_destroy(w);
    CHECK(entries(dir, NULL, 0) == 2); /* the log and the reference */

    long na, nb;
    unsigned char *a = read_all(path, &na), *b = read_all(ref, &nb);
    printf("written: %ld bytes; lcm_eventlog_write_event's: %ld bytes\n", na, nb);
    CHECK(a && b && na == nb && memcmp(a, b, (size_t)na) == 0);
    free(a);
    free(b);
    unlink(ref);
}

/* ---- 3.: read back */
static void test_read(const char *path, int nev)
{
    core_err err = {0};
    sim_log *L = sim_log_load(path, &err);
    CHECK(L != NULL);
    if (!L) {
        fprintf(stderr, "read back: %s\n", err.msg);
        return;
    }
    sim_log_summary s;
    sim_log_info(L, &s);
    printf("read back: %ld events, %ld states (%.3f-%.3f s), %ld ship states, %ld inputs of %d station '%s'\n",
           s.n_events, s.n_states, s.t0_s, s.t1_s, s.n_ship, s.n_inputs, s.n_stations, s.station);
    CHECK(s.n_events == nev && s.n_states == NSTATES && s.n_ship == NSTATES);
    CHECK(s.n_inputs == 1 && s.n_stations == 1 && !strcmp(s.station, "seat1") && s.n_inputs_bad == 0);
    CHECK(s.t0_s == 0.0 && s.t1_s == (double)(20000 * (NSTATES - 1)) * 1e-6);
    CHECK(s.sas == 1); /* the status's FLAG_SAS */
    sim_log_sample x;
    CHECK(sim_log_sample_at(L, (double)60000 * 1e-6, &x) == 0); /* the fourth state's time */
    CHECK(x.pos_S_m[0] == 1.0 && x.pos_S_m[2] == -6.0 + 0.1 * 3);
    CHECK(x.controls_pct[0] == 55.0); /* the station's input, taken at 0.04 s */
    CHECK_NEAR(x.vel_S_mps[2], 5.0, 1e-9);
    sim_log_state ls;
    CHECK(sim_log_state_at(L, s.t1_s, &ls) == 0 && ls.heli.pos_E_m.z == -6.0 + 0.1 * 9);
    CHECK(sim_log_state_at(L, 0.5, &ls) == 1);
    sim_run_info ri;
    CHECK(sim_log_run_info(L, &ri) == 0);
    CHECK(!strcmp(ri.scenario, "cg47_uh60a") && ri.seed == 7 && ri.sea.state == 3 && ri.rate_hz == 200.0);
    sim_log_destroy(L);
}

/* The SAS state of the status read back: engaged, off, unknown for a
 * status that says neither (a log of an older disim), and off in a status
 * of the older sim_status_t (without the control_* fields appended since,
 * under its own fingerprint: read as the newest). */
static void test_sas(const char *path)
{
    static const int32_t flags[4] = {DISIM_SIM_STATUS_T_FLAG_SAS | DISIM_SIM_STATUS_T_FLAG_ON_DECK,
                                     DISIM_SIM_STATUS_T_FLAG_SAS_OFF, DISIM_SIM_STATUS_T_FLAG_FREE_STREAM,
                                     DISIM_SIM_STATUS_T_FLAG_SAS_OFF};
    static const int want[4] = {1, 0, -1, 0};
    static event ev[MAXEV];
    for (int c = 0; c < 4; c++) {
        int nev = make_events(ev, flags[c]);
        if (c == 3) { /* the older sim_status_t: 23 bytes fewer, its fingerprint */
            static const unsigned char fp[8] = {0x7b, 0xe0, 0xef, 0x47, 0x87, 0x00, 0xcc, 0x8e};
            CHECK(!strcmp(ev[1].ch, DISIM_CH_SIM_STATUS));
            ev[1].n -= 23;
            memcpy(ev[1].buf, fp, sizeof fp);
        }
        core_err err = {0};
        sim_log_writer *w = sim_log_writer_create(path, &err);
        CHECK(w != NULL);
        if (!w)
            return;
        for (int i = 0; i < nev; i++)
            CHECK(sim_log_writer_write(w, ev[i].ch, ev[i].ts, ev[i].buf, ev[i].n, &err) == 0);
        CHECK(sim_log_writer_commit(w, &err) == 0);
        sim_log_writer_destroy(w);
        sim_log *L = sim_log_load(path, &err);
        CHECK(L != NULL);
        if (!L)
            continue;
        sim_log_summary s;
        sim_log_info(L, &s);
        printf("status flags %d: the SAS read back as %d (want %d)\n", (int)flags[c], s.sas, want[c]);
        CHECK(s.sas == want[c]);
        sim_log_destroy(L);
        unlink(path);
    }
}

static void expect_refused(const char *what, const char *path, const char *want1, const char *want2)
{
    core_err err = {0};
    sim_log *L = sim_log_load(path, &err);
    printf("%s: %s\n", what, err.msg);
    CHECK(L == NULL && strstr(err.msg, path) && strstr(err.msg, want1) && strstr(err.msg, want2));
    sim_log_destroy(L);
}

/* ---- 4.: truncated and corrupt */
static void test_bad(const char *dir, const char *path)
{
    long n;
    unsigned char *b = read_all(path, &n);
    CHECK(b != NULL);
    if (!b)
        return;
    char p[256];
    snprintf(p, sizeof p, "%s/truncated.log", dir);
    write_all(p, b, n - 10);
    expect_refused("truncated", p, "event ", "(truncated)");
    unlink(p);
    /* the third event starts after the first two: header, channel, data each */
    long at = 0;
    for (int k = 0; k < 2; k++) {
        uint32_t chlen = (uint32_t)b[at + 20] << 24 | (uint32_t)b[at + 21] << 16 | (uint32_t)b[at + 22] << 8 | b[at + 23];
        uint32_t dlen = (uint32_t)b[at + 24] << 24 | (uint32_t)b[at + 25] << 16 | (uint32_t)b[at + 26] << 8 | b[at + 27];
        at += 28 + (long)chlen + (long)dlen;
    }
    CHECK(at + 4 < n);
    if (at + 4 < n) {
        b[at] ^= 0xFF;
        snprintf(p, sizeof p, "%s/corrupt.log", dir);
        write_all(p, b, n);
        char want[64];
        snprintf(want, sizeof want, "event 3 (byte %ld)", at);
        expect_refused("corrupt", p, want, "no sync word");
        unlink(p);
    }
    free(b);
}

/* ---- 5., 6.: an uncommitted writer, errors */
static void test_uncommitted(const char *dir, const event *ev)
{
    char p[256], first[256];
    core_err err = {0};
    snprintf(p, sizeof p, "%s/uncommitted.log", dir);
    sim_log_writer *w = sim_log_writer_create(p, &err);
    CHECK(w != NULL);
    if (w) {
        CHECK(sim_log_writer_write(w, ev[0].ch, ev[0].ts, ev[0].buf, ev[0].n, &err) == 0);
        CHECK(sim_log_writer_write(w, "", 0, ev[0].buf, ev[0].n, &err) < 0 && strstr(err.msg, "uncommitted.log"));
        printf("an event without a channel: %s\n", err.msg);
        CHECK(entries(dir, first, sizeof first) == 1 && strstr(first, "uncommitted.log.tmp") == first);
    }
    sim_log_writer_destroy(w);
    CHECK(entries(dir, first, sizeof first) == 0);
    printf("destroyed before its commit: %d entries left\n", entries(dir, NULL, 0));

    snprintf(p, sizeof p, "%s/missing/run.log", dir);
    w = sim_log_writer_create(p, &err);
    printf("in a missing folder: %s\n", err.msg);
    CHECK(w == NULL && strstr(err.msg, p) && strstr(err.msg, "No such file"));

    /* a folder where the log goes: the rename fails */
    snprintf(p, sizeof p, "%s/a_folder", dir);
    CHECK(mkdir(p, 0700) == 0);
    w = sim_log_writer_create(p, &err);
    CHECK(w != NULL);
    if (w) {
        CHECK(sim_log_writer_write(w, ev[0].ch, ev[0].ts, ev[0].buf, ev[0].n, &err) == 0);
        CHECK(sim_log_writer_commit(w, &err) < 0 && strstr(err.msg, p) && strstr(err.msg, "nothing written"));
        printf("committed over a folder: %s\n", err.msg);
    }
    sim_log_writer_destroy(w);
    CHECK(entries(dir, first, sizeof first) == 1 && !strcmp(first, "a_folder"));
    rmdir(p);

    /* a disk that fills (a file-size limit: EFBIG, as ENOSPC would be):
     * the message names the log and the system's reason, nothing is left */
    snprintf(p, sizeof p, "%s/full.log", dir);
    struct rlimit old_lim, lim;
    CHECK(getrlimit(RLIMIT_FSIZE, &old_lim) == 0);
    void (*old_sig)(int) = signal(SIGXFSZ, SIG_IGN);
    lim = old_lim;
    lim.rlim_cur = 4096;
    w = sim_log_writer_create(p, &err);
    CHECK(w != NULL && setrlimit(RLIMIT_FSIZE, &lim) == 0);
    int rc = 0;
    for (int i = 0; w && i < 10000 && rc == 0; i++)
        rc = sim_log_writer_write(w, ev[0].ch, ev[0].ts, ev[0].buf, ev[0].n, &err);
    if (w && rc == 0)
        rc = sim_log_writer_commit(w, &err);
    CHECK(setrlimit(RLIMIT_FSIZE, &old_lim) == 0);
    signal(SIGXFSZ, old_sig);
    CHECK(rc < 0 && strstr(err.msg, p) && strstr(err.msg, strerror(EFBIG)));
    printf("a disk that fills: %s\n", err.msg);
    if (w)
        CHECK(sim_log_writer_commit(w, &err) < 0 && strstr(err.msg, strerror(EFBIG)) && strstr(err.msg, "nothing written"));
    sim_log_writer_destroy(w);
    CHECK(entries(dir, first, sizeof first) == 0);
}

/* ---- 7.: hostile files */
static void write_events(const char *path, const event *ev, int n)
{
    core_err err = {0};
    sim_log_writer *w = sim_log_writer_create(path, &err);
    CHECK(w != NULL);
    if (!w)
        return;
    for (int i = 0; i < n; i++)
        CHECK(sim_log_writer_write(w, ev[i].ch, ev[i].ts, ev[i].buf, ev[i].n, &err) == 0);
    CHECK(sim_log_writer_commit(w, &err) == 0);
    sim_log_writer_destroy(w);
}

static void test_hostile(const char *dir)
{
    char p[256];
    core_err err = {0};
    sim_log_frames fr;
    /* an event whose data length is 0x7FFFFFFF: refused before LCM's
     * reader sees it, the sizes said without an int overflow */
    static const unsigned char huge[] = {0xED, 0xA1, 0xDA, 0x01, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
                                         0, 0, 0, 17, 0x7F, 0xFF, 0xFF, 0xFF, 'D', 'I', 'S', 'I', 'M', '_', 'P', 'I',
                                         'L', 'O', 'T', '_', 'I', 'N', 'P', 'U', 'T', 1, 2, 3, 4, 5, 6, 7, 8};
    snprintf(p, sizeof p, "%s/huge.log", dir);
    write_all(p, huge, sizeof huge);
    expect_refused("0x7FFFFFFF data bytes", p, "2147483664 bytes of channel and data", "(truncated)");
    CHECK(sim_log_check_frames(p, &fr, &err) < 0 && strstr(err.msg, "2147483664 bytes") && strstr(err.msg, "event 1"));
    unlink(p);
    /* not regular files: refused unread (/dev/zero would never end) */
    expect_refused("/dev/zero", "/dev/zero", "a character device", "regular file");
    CHECK(sim_log_check_frames("/dev/zero", &fr, &err) < 0 && strstr(err.msg, "a character device"));
    expect_refused("a folder", dir, "a folder", "regular file");
    /* a heli_state_t whose quaternion has infinities: refused, as the renderer refuses it */
    static event ev[MAXEV];
    int n = make_events(ev, DISIM_SIM_STATUS_T_FLAG_SAS);
    for (int i = 0, k = 0; i < n; i++) {
        if (strcmp(ev[i].ch, DISIM_CH_HELI_STATE) || k++ != 4)
            continue;
        disim_heli_state_t h;
        CHECK(disim_heli_state_t_decode(ev[i].buf, 0, ev[i].n, &h) == ev[i].n);
        h.quat_EB[1] = INFINITY;
        h.quat_EB[2] = -INFINITY;
        ev[i].n = disim_heli_state_t_encode(ev[i].buf, 0, sizeof ev[i].buf, &h);
        disim_heli_state_t_decode_cleanup(&h);
    }
    snprintf(p, sizeof p, "%s/inf_quat.log", dir);
    write_events(p, ev, n);
    expect_refused("a quaternion with infinities", p, "heli_state_t.quat_EB", "unit quaternion");
    /* framed well: every event counted, the one input */
    CHECK(sim_log_check_frames(p, &fr, &err) == 0 && fr.n_events == n && fr.n_inputs == 1 &&
          fr.size == file_size(p));
    unlink(p);
}

int main(void)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    char dir[64], path[128];
    snprintf(dir, sizeof dir, "/tmp/test_log_%d", (int)getpid());
    if (mkdir(dir, 0700) != 0) {
        perror(dir);
        CHECK(0);
        return check_done("test_log");
    }
    snprintf(path, sizeof path, "%s/run.log", dir);
    static event ev[MAXEV];
    int nev = make_events(ev, DISIM_SIM_STATUS_T_FLAG_SAS);
    CHECK(nev == 2 + 2 * NSTATES + 1);
    for (int i = 0; i < nev; i++)
        CHECK(ev[i].n > 0);
    test_write(dir, path, ev, nev);
    test_read(path, nev);
    test_bad(dir, path);
    unlink(path);
    test_uncommitted(dir, ev);
    test_sas(path);
    test_hostile(dir);
    CHECK(rmdir(dir) == 0);
    return check_done("test_log");
}
