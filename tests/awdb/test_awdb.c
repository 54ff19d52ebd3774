/* test_awdb.c -- the airwake database and builder: canonical keys, CRC-64,
 * one build per key however often it is asked for, corrupt and torn fields
 * detected and rebuilt, warm starts from the nearest field, failures kept
 * with their reason, a second builder refused, a builder killed with
 * SIGKILL mid-build leaving a consistent database that a restart finishes,
 * SIGTERM putting the running request back at the front of the queue, and
 * the builder's progress files as a client reads them, the builder's
 * order (a mirror image at once, waited-for requests first) and the quick
 * level's warm starts.
 * The engine here is mostly a test engine that writes a small file derived
 * from the key: what is under test is the database's bookkeeping. Once,
 * the embedded CFD engine builds a field through the builder (a coarse
 * SFS2, a few iterations) so that the real engine's temporary and its
 * rename are exercised too (test_embedded). */
#include "awdb.h"
#include "awdb_private.h" /* the request file format (awdb_key_format, awdb_key_read) */
#include "cfd.h"          /* test_embedded reads back the field it built */
#include "check.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

typedef struct test_engine {
    int builds;
    int fail_speed_cmps; /* fail when the speed (cm/s) equals this */
    double sleep_s;      /* per build, in steps, to be killed in the middle */
    char last_warm[1024];
    const char *db_dir;  /* when set: each build counts the temporaries it finds at its start */
    int stray_at_start;
    int norder; /* the builds' speeds (cm/s), in the order they started */
    int order_cmps[8];
} test_engine;

static int count_tmp(const char *dir, const char *sub);

static test_engine te_init(double sleep_s)
{
    test_engine te;
    memset(&te, 0, sizeof te);
    te.fail_speed_cmps = -1;
    te.sleep_s = sleep_s;
    return te;
}

static int te_build(void *user, const awdb_key *k, const char *warm, const char *out,
                    awdb_progress_fn progress, void *pu, core_err *err)
{
    test_engine *te = user;
    te->builds++;
    snprintf(te->last_warm, sizeof te->last_warm, "%s", warm ? warm : "");
    if (te->db_dir)
        te->stray_at_start += count_tmp(te->db_dir, "fields");
    if (te->norder < 8)
        te->order_cmps[te->norder++] = (int)(k->wod_speed_mps * 100 + 0.5);
    if ((int)(k->wod_speed_mps * 100 + 0.5) == te->fail_speed_cmps)
        return core_err_set(err, -1, "diverged at iteration 17 (test)");
    FILE *f = fopen(out, "w");
    if (!f)
        return core_err_set(err, -1, "%s: cannot write", out);
    for (int i = 0; i < 10; i++) {
        fprintf(f, "%s %.2f %.4f step %d\n", k->ship, k->wod_speed_mps, k->wod_dir_rad, i);
        fflush(f);
        if (te->sleep_s > 0) {
            struct timespec ts = {0, (long)(te->sleep_s / 10 * 1e9)};
            nanosleep(&ts, NULL);
        }
        if (progress(pu, (i + 1) / 10.0, 1e-3 / (i + 1), i))
            break;
    }
    fclose(f);
    return 0;
}

static awdb_key key(double v, double dir_deg)
{
    awdb_key k;
    memset(&k, 0, sizeof k);
    snprintf(k.ship, sizeof k.ship, "CG-47");
    snprintf(k.aircraft, sizeof k.aircraft, "UH-60A");
    k.wod_speed_mps = v;
    k.wod_dir_rad = dir_deg * CORE_DEG_TO_RAD;
    k.rotor = CORE_ROTOR_UNIFORM;
    k.thrust_N = 72950.4;
    k.station_S_m[2] = -6.0;
    k.radius_m = 8.18;
    k.shaft_pitch_rad = 0.05;
    k.grid = CORE_GRID_COARSE;
    return k;
}

static int count(const char *dir, const char *sub, const char *suffix)
{
    char p[1024];
    snprintf(p, sizeof p, "%s/%s", dir, sub);
    DIR *d = opendir(p);
    int c = 0;
    struct dirent *e;
    while (d && (e = readdir(d))) {
        size_t l = strlen(e->d_name), s = strlen(suffix);
        if (e->d_name[0] != '.' && l >= s && !strcmp(e->d_name + l - s, suffix))
            c++;
        if (!strncmp(e->d_name, ".tmp", 4))
            c += 1000; /* stray temporaries count loudly */
    }
    if (d)
        closedir(d);
    return c;
}

/* Entries of dir/sub named as the builder's temporaries (".tmp-NAME.h5"
 * and the engine's side files beside it). */
static int count_tmp(const char *dir, const char *sub)
{
    char p[1024];
    snprintf(p, sizeof p, "%s/%s", dir, sub);
    DIR *d = opendir(p);
    int c = 0;
    struct dirent *e;
    while (d && (e = readdir(d)))
        c += !strncmp(e->d_name, ".tmp-", 5);
    if (d)
        closedir(d);
    return c;
}

/* Whether the queue's first request (in the builder's order: file names
 * sorted) is the one for name. */
static int queue_first_is(const char *dir, const char *name)
{
    char p[1024], first[600] = "";
    snprintf(p, sizeof p, "%s/queue", dir);
    DIR *d = opendir(p);
    struct dirent *e;
    while (d && (e = readdir(d))) {
        size_t l = strlen(e->d_name);
        if (e->d_name[0] == '.' || l < 5 || strcmp(e->d_name + l - 4, ".req"))
            continue;
        if (!first[0] || strcmp(e->d_name, first) < 0)
            snprintf(first, sizeof first, "%s", e->d_name);
    }
    if (d)
        closedir(d);
    const char *stem = strchr(first, '-');
    return stem && !strncmp(stem + 1, name, strlen(name)) && !strcmp(stem + 1 + strlen(name), ".req");
}

static volatile sig_atomic_t no_stop = 0;
static volatile sig_atomic_t term_flag = 0;
static void on_term(int sig)
{
    (void)sig;
    term_flag = 1;
}

static int run_builder(awdb *db, test_engine *te, int jobs, core_err *err)
{
    awdb_engine eng = {"test", te_build, te, NULL};
    awdb_builder_opts o = {jobs, 1, 0.01, NULL, NULL, NULL, NULL, 0.0};
    return awdb_builder_run(db, &eng, &o, &no_stop, err);
}

static void test_keys(void)
{
    core_err err = {0};
    awdb_key a = key(15.0, -30.0), b = key(15.001, -30.001);
    CHECK(awdb_key_canon(&a, &err) == 0 && awdb_key_canon(&b, &err) == 0);
    char na[200], nb[200];
    awdb_key_name(&a, na, sizeof na);
    awdb_key_name(&b, nb, sizeof nb);
    CHECK(strcmp(na, nb) == 0);
    CHECK(strstr(na, "CG-47_UH-60A_v15.00_d-030.00_uniform_coarse_") == na);
    awdb_key c = key(15.0, 30.0);
    awdb_key_canon(&c, &err);
    awdb_key_name(&c, nb, sizeof nb);
    CHECK(strcmp(na, nb) != 0);
    /* A ship-only field ignores the helicopter. */
    awdb_key s1 = key(10, 0), s2 = key(10, 0);
    s1.rotor = s2.rotor = CORE_ROTOR_OFF;
    snprintf(s2.aircraft, sizeof s2.aircraft, "SA365N");
    s2.thrust_N = 1;
    awdb_key_canon(&s1, &err);
    awdb_key_canon(&s2, &err);
    awdb_key_name(&s1, na, sizeof na);
    awdb_key_name(&s2, nb, sizeof nb);
    CHECK(strcmp(na, nb) == 0 && strstr(na, "shiponly") != NULL);
    /* A hover in calm air is one field whatever the direction asked. */
    awdb_key h1 = key(0, 60), h2 = key(0, -90);
    CHECK(awdb_key_canon(&h1, &err) == 0 && awdb_key_canon(&h2, &err) == 0);
    awdb_key_name(&h1, na, sizeof na);
    awdb_key_name(&h2, nb, sizeof nb);
    CHECK(strcmp(na, nb) == 0 && strstr(na, "_v00.00_d+000.00_") != NULL);
    /* A deck-zone key: its own name, its reference speed in the request
     * file; none in calm air; a zone's ship-only field keeps the station,
     * radius and aircraft that place the zone (two stations, two fields);
     * whole-domain names as before (the same hash). */
    {
        awdb_key w = key(10, -30), z = key(10, -30), zoff = key(10, -30), zoff2 = key(10, -30), zcalm = key(0, 0);
        z.zone_ref_mps = zoff.zone_ref_mps = zoff2.zone_ref_mps = zcalm.zone_ref_mps = 15.0;
        zoff.rotor = zoff2.rotor = CORE_ROTOR_OFF;
        zoff2.station_S_m[0] += 1.0;
        CHECK(awdb_key_canon(&w, &err) == 0 && awdb_key_canon(&z, &err) == 0 && awdb_key_canon(&zoff, &err) == 0 &&
              awdb_key_canon(&zoff2, &err) == 0 && awdb_key_canon(&zcalm, &err) == 0);
        CHECK(zcalm.zone_ref_mps == 0.0);
        CHECK(zoff.zone_ref_mps == 15.0 && zoff.thrust_N == 0.0 && zoff.radius_m > 0.0 && zoff.aircraft[0]);
        char no[200], no2[200];
        awdb_key_name(&zoff, no, sizeof no);
        awdb_key_name(&zoff2, no2, sizeof no2);
        CHECK(strstr(no, "_off_coarse-zone_") != NULL && strcmp(no, no2) != 0);
        awdb_key zbad = zoff;
        zbad.radius_m = 0.0;
        CHECK(awdb_key_canon(&zbad, &err) < 0 && strstr(err.msg, "radius_m") != NULL);
        awdb_key_name(&w, na, sizeof na);
        awdb_key_name(&z, nb, sizeof nb);
        CHECK(strstr(na, "_uniform_coarse_") != NULL && strstr(nb, "_uniform_coarse-zone_") != NULL);
        CHECK(strcmp(na + strlen(na) - 16, nb + strlen(nb) - 16) != 0);
        char text[8192], path[] = "/tmp/disim_awdb_zone_XXXXXX";
        awdb_key_format(&z, text, sizeof text);
        CHECK(strstr(text, "zone_ref_mps = 15") != NULL);
        int fd = mkstemp(path);
        CHECK(fd >= 0);
        if (fd >= 0) {
            CHECK(write(fd, text, strlen(text)) == (ssize_t)strlen(text));
            close(fd);
            core_ini *ini = core_ini_load(path, &err);
            awdb_key back;
            CHECK(ini && awdb_key_read(ini, &back, &err) == 0);
            CHECK(back.zone_ref_mps == 15.0);
            core_ini_destroy(ini);
            remove(path);
        }
        z.zone_ref_mps = -1.0;
        CHECK(awdb_key_canon(&z, &err) < 0 && strstr(err.msg, "zone_ref_mps") != NULL);
    }
    /* Bad keys name the field. */
    awdb_key bad = key(-1, 0);
    CHECK(awdb_key_canon(&bad, &err) < 0 && strstr(err.msg, "wod_speed_mps") != NULL);
    bad = key(10, 0);
    bad.thrust_N = 0;
    CHECK(awdb_key_canon(&bad, &err) < 0 && strstr(err.msg, "thrust_N") != NULL);
    bad = key(10, 0);
    bad.radius_m = 0;
    CHECK(awdb_key_canon(&bad, &err) < 0 && strstr(err.msg, "radius_m") != NULL);
    /* Shaft tilt resolves to 0.1 deg: 2.86 and 2.87 deg are one field, 3.0 another. */
    awdb_key t1 = key(10, 0), t2 = key(10, 0), t3 = key(10, 0);
    t1.shaft_pitch_rad = 2.86 * CORE_DEG_TO_RAD;
    t2.shaft_pitch_rad = 2.87 * CORE_DEG_TO_RAD;
    t3.shaft_pitch_rad = 3.0 * CORE_DEG_TO_RAD;
    awdb_key_canon(&t1, &err);
    awdb_key_canon(&t2, &err);
    awdb_key_canon(&t3, &err);
    awdb_key_name(&t1, na, sizeof na);
    awdb_key_name(&t2, nb, sizeof nb);
    CHECK(strcmp(na, nb) == 0);
    awdb_key_name(&t3, nb, sizeof nb);
    CHECK(strcmp(na, nb) != 0);
    /* A key at a limit stays inside it when rounded (the fuzzer's finds: a
     * shaft roll of 1 rad rounded to 57.3 deg, 1.00007 rad, a radius of
     * 49.996 m to 50 m, a thrust of 0.2 N to none, so the canonical key
     * was refused by a second canon and its request file by the builder's
     * reader). */
    {
        awdb_key e1 = key(10, 0), e2 = key(10, 0);
        e1.shaft_roll_rad = 1.0;
        e1.shaft_pitch_rad = -1.0;
        e2.radius_m = 49.996;
        e2.thrust_N = 0.2; /* rounded to 0 N, refused as no thrust when read back */
        for (int i = 0; i < 2; i++) {
            awdb_key *e = i ? &e2 : &e1, again;
            CHECK(awdb_key_canon(e, &err) == 0);
            again = *e;
            CHECK(awdb_key_canon(&again, &err) == 0);
            char text[8192], n1[200], n2[200];
            awdb_key_format(e, text, sizeof text);
            core_ini *ini = core_ini_parse(text, strlen(text), "edge.req", &err);
            awdb_key back;
            memset(&back, 0, sizeof back);
            int ok = ini && awdb_key_read(ini, &back, &err) == 0 && awdb_key_canon(&back, &err) == 0;
            CHECK(ok);
            if (!ok)
                fprintf(stderr, "  edge key %d: %s\n", i, err.msg);
            core_ini_destroy(ini);
            awdb_key_name(e, n1, sizeof n1);
            awdb_key_name(&back, n2, sizeof n2);
            CHECK(strcmp(n1, n2) == 0);
        }
        CHECK(fabs(e1.shaft_roll_rad) <= 1.0 && fabs(e1.shaft_pitch_rad) <= 1.0 && e2.radius_m < 50.0);
    }
    /* a name starting with '.' would make a hidden field file that the
     * database's listings skip (the fuzzer's find: ship ".i-GC47") */
    bad = key(10, 0);
    snprintf(bad.ship, sizeof bad.ship, ".i-GC47");
    CHECK(awdb_key_canon(&bad, &err) < 0 && strstr(err.msg, "ship '.i-GC47'") != NULL);
    bad = key(10, 0);
    snprintf(bad.aircraft, sizeof bad.aircraft, ".UH-60A");
    CHECK(awdb_key_canon(&bad, &err) < 0 && strstr(err.msg, "aircraft '.UH-60A'") != NULL);
    bad = key(10, 0);
    snprintf(bad.ship, sizeof bad.ship, "a/b");
    CHECK(awdb_key_canon(&bad, &err) < 0 && strstr(err.msg, "ship 'a/b'") != NULL);
    /* A thrust the request file's reader refuses (over 1e7 N) is refused
     * when asked for, not queued to fail in the builder. */
    bad = key(10, 0);
    bad.thrust_N = 2e7;
    CHECK(awdb_key_canon(&bad, &err) < 0 && strstr(err.msg, "thrust_N") != NULL);
    /* Names that do not fit a file name with their hash are refused: cut,
     * two keys (here two thrusts) would share one field. */
    {
        awdb_key l1 = key(10, 0), l2 = key(10, 0);
        memset(l1.ship, 'S', sizeof l1.ship - 1); /* the longest the key holds */
        memset(l1.aircraft, 'A', sizeof l1.aircraft - 1);
        memcpy(l2.ship, l1.ship, sizeof l1.ship);
        memcpy(l2.aircraft, l1.aircraft, sizeof l1.aircraft);
        l2.thrust_N = 60000.0;
        int r1 = awdb_key_canon(&l1, &err), r2 = awdb_key_canon(&l2, &err);
        CHECK(r1 < 0 && r2 < 0 && strstr(err.msg, "too long") != NULL);
        if (r1 == 0 && r2 == 0) {
            awdb_key_name(&l1, na, sizeof na);
            awdb_key_name(&l2, nb, sizeof nb);
            CHECK(strcmp(na, nb) != 0); /* what canon's refusal prevents */
        }
        l1 = key(10, 0); /* the longest that fits is taken */
        memset(l1.ship, 'S', 90);
        memset(l1.aircraft, 'A', 40);
        CHECK(awdb_key_canon(&l1, &err) == 0);
        awdb_key_name(&l1, na, sizeof na);
        CHECK(strlen(na) < AWDB_NAME_MAX - 1);
    }
}

static void test_crc(const char *dir)
{
    /* CRC-64/XZ check value of "123456789". */
    char p[1024];
    snprintf(p, sizeof p, "%s/crc.txt", dir);
    FILE *f = fopen(p, "w");
    fputs("123456789", f);
    fclose(f);
    uint64_t crc = 0, size = 0;
    core_err err;
    CHECK(awdb_file_crc64(p, &crc, &size, &err) == 0);
    CHECK(crc == 0x995DC9BBDF1939FAULL && size == 9);
    remove(p);
}

static void test_flow(const char *dir)
{
    core_err err = {0};
    awdb *db = awdb_open(dir, NULL, &err);
    awdb *db2 = awdb_open(dir, NULL, &err); /* a second client */
    CHECK(db && db2);
    test_engine te = te_init(0);
    awdb_key k1 = key(10, 0), k2 = key(12, 0), k3 = key(10, 30);
    awdb_state st;
    CHECK(awdb_submit(db, &k1, &st, &err) == 0 && st == AWDB_ABSENT);
    CHECK(awdb_submit(db2, &k1, &st, &err) == 0 && st == AWDB_QUEUED); /* not twice */
    awdb_key_canon(&k1, &err);
    CHECK(awdb_query(db2, &k1, NULL, 0) == AWDB_QUEUED);
    CHECK(count(dir, "queue", ".req") == 1);
    CHECK(run_builder(db, &te, 2, &err) == 0);
    CHECK(te.builds == 1);
    char path[1024];
    CHECK(awdb_query(db2, &k1, path, sizeof path) == AWDB_READY);
    CHECK(strstr(path, "/fields/CG-47_UH-60A_v10.00_d+000.00_") != NULL);
    CHECK(awdb_submit(db2, &k1, &st, &err) == 0 && st == AWDB_READY);
    CHECK(count(dir, "queue", ".req") == 0);

    /* Warm start from the nearest finished field. */
    CHECK(awdb_submit(db, &k2, &st, &err) == 0);
    CHECK(run_builder(db, &te, 1, &err) == 0);
    CHECK(te.builds == 2 && strcmp(te.last_warm, path) == 0);
    /* Green 30 does not start from the head wind: its wind crosses the
     * side faces, which are symmetry planes in a head wind. */
    CHECK(awdb_submit(db, &k3, &st, &err) == 0);
    CHECK(run_builder(db, &te, 1, &err) == 0);
    CHECK(te.builds == 3 && te.last_warm[0] == '\0');
    awdb_key kh = key(10.5, 0);
    CHECK(awdb_submit(db, &kh, &st, &err) == 0);
    CHECK(run_builder(db, &te, 1, &err) == 0);
    CHECK(strstr(te.last_warm, "v10.00_d+000.00") != NULL); /* 10 m/s head is nearer than 12 */
    /* No warm start from a direction more than 30 deg away: green 60 may
     * start from green 30, green 90 from nothing (the inflow). */
    char near[1024];
    awdb_key kg60 = key(10, 60), kg90 = key(10, 90);
    awdb_key_canon(&kg60, &err);
    awdb_key_canon(&kg90, &err);
    CHECK(awdb_nearest(db, &kg60, near, sizeof near) == 0 && strstr(near, "v10.00_d+030.00") != NULL);
    CHECK(awdb_nearest(db, &kg90, near, sizeof near) == 1);
    /* Nor green 90 from green 60, 30 deg away: a beam wind's fore and aft
     * faces are symmetry planes, green 60's an inlet and an outlet. */
    CHECK(awdb_submit(db, &kg60, &st, &err) == 0);
    CHECK(run_builder(db, &te, 1, &err) == 0);
    CHECK(awdb_query(db, &kg60, NULL, 0) == AWDB_READY);
    CHECK(awdb_nearest(db, &kg90, near, sizeof near) == 1);
    awdb_key kg75 = key(10, 75);
    awdb_key_canon(&kg75, &err);
    CHECK(awdb_nearest(db, &kg75, near, sizeof near) == 0 && strstr(near, "v10.00_d+060.00") != NULL);
    /* Of two fields of the same wind, the one with the nearer rotor (the
     * previous coupling iteration's), in either order of building. */
    {
        awdb_key ta = key(10, 60), tb = key(10, 60), tq = key(10, 60);
        ta.thrust_N = 60000.0;
        tb.thrust_N = 75000.0;
        tq.thrust_N = 74000.0;
        awdb_key_canon(&ta, &err);
        awdb_key_canon(&tb, &err);
        awdb_key_canon(&tq, &err);
        char nb_[200];
        awdb_key_name(&tb, nb_, sizeof nb_);
        CHECK(awdb_submit(db, &tb, &st, &err) == 0 && run_builder(db, &te, 1, &err) == 0);
        CHECK(awdb_submit(db, &ta, &st, &err) == 0 && run_builder(db, &te, 1, &err) == 0);
        CHECK(awdb_nearest(db, &tq, near, sizeof near) == 0 && strstr(near, nb_) != NULL);
        tq.thrust_N = 61000.0;
        awdb_key_name(&ta, nb_, sizeof nb_);
        CHECK(awdb_nearest(db, &tq, near, sizeof near) == 0 && strstr(near, nb_) != NULL);
        /* The best field fails its checksum: the next best (the green 60
         * field built above) still gives a warm start (it gave a cold
         * one). */
        char bad[1400];
        snprintf(bad, sizeof bad, "%s/fields/%s.h5", dir, nb_);
        FILE *cf = fopen(bad, "ab"); /* a changed size: the mtime may not tick */
        CHECK(cf != NULL);
        if (cf) {
            fputc('x', cf);
            fclose(cf);
        }
        awdb_key_name(&kg60, nb_, sizeof nb_); /* thrust 72950 N: the next nearest to 61000 */
        CHECK(awdb_nearest(db, &tq, near, sizeof near) == 0 && strstr(near, nb_) != NULL);
        CHECK(awdb_query(db, &ta, NULL, 0) != AWDB_READY); /* and it is not served */
    }

    /* A whole-domain ship-only field never starts from another wind's (its
     * state would follow its start), only from its own wind's on a coarser
     * grid: quick, then coarse, then default; a deck zone's ship-only
     * field may start from another wind's. */
    {
        awdb_key s30 = key(10, 30), s60 = key(10, 60);
        s30.rotor = s60.rotor = CORE_ROTOR_OFF;
        s30.thrust_N = s60.thrust_N = 0.0;
        awdb_key s30q = s30;
        s30q.grid = CORE_GRID_QUICK;
        char nq[200], nc[200];
        CHECK(awdb_key_canon(&s30q, &err) == 0);
        awdb_key_name(&s30q, nq, sizeof nq);
        CHECK(strstr(nq, "CG-47_shiponly_v10.00_d+030.00_off_quick_") == nq);
        CHECK(awdb_submit(db, &s30q, &st, &err) == 0);
        CHECK(run_builder(db, &te, 1, &err) == 0);
        CHECK(te.last_warm[0] == '\0'); /* the quick level starts from the inflow */
        CHECK(awdb_submit(db, &s30, &st, &err) == 0);
        CHECK(run_builder(db, &te, 1, &err) == 0);
        CHECK(strstr(te.last_warm, nq) != NULL); /* coarse from its own wind's quick field */
        CHECK(awdb_key_canon(&s60, &err) == 0);
        CHECK(awdb_nearest(db, &s60, near, sizeof near) == 1);
        awdb_key s30d = s30;
        s30d.grid = CORE_GRID_DEFAULT;
        CHECK(awdb_key_canon(&s30d, &err) == 0 && awdb_key_canon(&s30, &err) == 0);
        awdb_key_name(&s30, nc, sizeof nc);
        CHECK(awdb_nearest(db, &s30d, near, sizeof near) == 0 && strstr(near, nc) != NULL); /* the finest */
        /* another speed of the same direction is another wind */
        awdb_key s30v = s30d;
        s30v.wod_speed_mps = 12.0;
        CHECK(awdb_key_canon(&s30v, &err) == 0 && awdb_nearest(db, &s30v, near, sizeof near) == 1);
        /* built: from the inflow, with the green 30 fields finished */
        CHECK(awdb_submit(db, &s60, &st, &err) == 0);
        CHECK(run_builder(db, &te, 1, &err) == 0);
        CHECK(te.last_warm[0] == '\0');
    }
    /* Coarse-to-fine: a default-grid key with no default-grid neighbour
     * starts from the coarse field of its wind; once a default-grid
     * neighbour exists, from that; never from a finer grid. */
    {
        awdb_key kd = key(10, 0), kd2 = key(10.5, 0), kc = key(10, 0);
        kd.grid = kd2.grid = 1;
        awdb_key_canon(&kd, &err);
        awdb_key_canon(&kd2, &err);
        awdb_key_canon(&kc, &err);
        CHECK(awdb_nearest(db, &kd, near, sizeof near) == 0 && strstr(near, "v10.00_d+000.00_uniform_coarse") != NULL);
        CHECK(awdb_submit(db, &kd, &st, &err) == 0 && run_builder(db, &te, 1, &err) == 0);
        CHECK(strstr(te.last_warm, "v10.00_d+000.00_uniform_coarse") != NULL);
        CHECK(awdb_nearest(db, &kd2, near, sizeof near) == 0 && strstr(near, "v10.00_d+000.00_uniform_default") != NULL);
        CHECK(awdb_nearest(db, &kc, near, sizeof near) == 0 && strstr(near, "_coarse_") != NULL);
    }

    /* A corrupted field is detected, removed and rebuilt. */
    FILE *f = fopen(path, "r+");
    fseek(f, 3, SEEK_SET);
    fputc('#', f);
    fclose(f);
    awdb *db3 = awdb_open(dir, NULL, &err); /* a fresh client: no verification cache */
    CHECK(awdb_query(db3, &k1, NULL, 0) == AWDB_ABSENT);
    CHECK(awdb_submit(db3, &k1, &st, &err) == 0 && st == AWDB_ABSENT);
    CHECK(run_builder(db3, &te, 1, &err) == 0);
    CHECK(te.builds == 12);
    awdb_close(db3);
    db3 = awdb_open(dir, NULL, &err);
    CHECK(awdb_query(db3, &k1, NULL, 0) == AWDB_READY);
    /* An entry copied under another key's name, its checksum intact, is
     * not that key's field: the .sum's key must name the entry. */
    {
        awdb_key kx = key(17, 0);
        awdb_key_canon(&kx, &err);
        char xn[200], xh5[1300], xsum[1300], sum1[1100], cmd[4000];
        awdb_key_name(&kx, xn, sizeof xn);
        snprintf(xh5, sizeof xh5, "%s/fields/%s.h5", dir, xn);
        snprintf(xsum, sizeof xsum, "%s/fields/%s.sum", dir, xn);
        snprintf(sum1, sizeof sum1, "%.*s.sum", (int)(strlen(path) - 3), path);
        snprintf(cmd, sizeof cmd, "cp '%s' '%s' && cp '%s' '%s'", path, xh5, sum1, xsum);
        CHECK(system(cmd) == 0);
        awdb *dbx = awdb_open(dir, NULL, &err);
        CHECK(awdb_query(dbx, &k1, NULL, 0) == AWDB_READY);
        CHECK(awdb_query(dbx, &kx, NULL, 0) == AWDB_ABSENT);
        awdb_close(dbx);
        remove(xh5);
        remove(xsum);
    }
    /* A torn entry (field without its checksum) is not READY. */
    char sum[1100];
    snprintf(sum, sizeof sum, "%.*s.sum", (int)(strlen(path) - 3), path);
    CHECK(remove(sum) == 0);
    awdb_close(db3);
    db3 = awdb_open(dir, NULL, &err);
    CHECK(awdb_query(db3, &k1, NULL, 0) == AWDB_ABSENT);
    awdb_close(db3);

    /* A failing build is kept with its reason and can be asked for again. */
    te.fail_speed_cmps = 1400;
    awdb_key k4 = key(14, 0);
    CHECK(awdb_submit(db, &k4, &st, &err) == 0);
    CHECK(run_builder(db, &te, 1, &err) == 0);
    awdb_key_canon(&k4, &err);
    CHECK(awdb_query(db, &k4, NULL, 0) == AWDB_FAILED);
    char name[200], fp[1400], line[256] = "";
    awdb_key_name(&k4, name, sizeof name);
    snprintf(fp, sizeof fp, "%s/failed/%s.txt", dir, name);
    f = fopen(fp, "r");
    CHECK(f && fgets(line, sizeof line, f));
    if (f)
        fclose(f);
    CHECK(strstr(line, "diverged at iteration 17") != NULL);
    /* a reader asking for it is told where the reason is and how to build
     * it again, and waits for nothing */
    awdb_fields_opts fo;
    awdb_fields_opts_default(&fo);
    awdb_fields *fc = awdb_fields_create(db, &fo, NULL, &err);
    CHECK(fc != NULL);
    if (fc) {
        awdb_key k4b = k4;
        err.msg[0] = '\0';
        CHECK(awdb_fields_get(fc, &k4b, &err) == NULL && strstr(err.msg, fp) != NULL &&
              strstr(err.msg, "remove that file") != NULL);
        awdb_fields_destroy(fc);
    }
    te.fail_speed_cmps = -1;
    CHECK(awdb_submit(db, &k4, &st, &err) == 0 && st == AWDB_FAILED);
    CHECK(run_builder(db, &te, 1, &err) == 0);
    CHECK(awdb_query(db, &k4, NULL, 0) == AWDB_READY);

    /* A corrupt request file goes to failed/ with the line named. */
    snprintf(fp, sizeof fp, "%s/queue/00000001-CG-47_bad.req", dir);
    f = fopen(fp, "w");
    fputs("[key]\nship = CG-47\naircraft = UH-60A\nwod_speed_mps = fast\n", f);
    fclose(f);
    CHECK(run_builder(db, &te, 1, &err) == 0);
    snprintf(fp, sizeof fp, "%s/failed/CG-47_bad.txt", dir);
    f = fopen(fp, "r");
    CHECK(f && fgets(line, sizeof line, f));
    if (f)
        fclose(f);
    CHECK(strstr(line, ":4: [key] wod_speed_mps = 'fast': expected a number") != NULL);
    /* A request another program wrote, its file name consistent with its
     * key, but a key awdb_submit refuses (the rotor on without thrust): it
     * fails naming the field, and nothing is built. */
    {
        awdb_key nc = key(16, 0);
        nc.thrust_N = 0.0;
        char ncn[200], text[AWDB_KEY_TEXT];
        awdb_key_name(&nc, ncn, sizeof ncn);
        awdb_key_format(&nc, text, sizeof text);
        snprintf(fp, sizeof fp, "%s/queue/00000002-%s.req", dir, ncn);
        f = fopen(fp, "w");
        CHECK(f != NULL);
        if (f) {
            fputs(text, f);
            fclose(f);
        }
        int builds = te.builds;
        CHECK(run_builder(db, &te, 1, &err) == 0);
        CHECK(te.builds == builds);
        snprintf(fp, sizeof fp, "%s/failed/%s.txt", dir, ncn);
        line[0] = '\0';
        f = fopen(fp, "r");
        CHECK(f && fgets(line, sizeof line, f));
        if (f)
            fclose(f);
        CHECK(strstr(line, ".req: airwake key: thrust_N = 0") != NULL);
        snprintf(fp, sizeof fp, "%s/fields/%s.h5", dir, ncn);
        CHECK(access(fp, F_OK) != 0);
    }
    awdb_close(db);
    awdb_close(db2);
}

static void test_kill(const char *dir)
{
    core_err err = {0};
    awdb *db = awdb_open(dir, NULL, &err);
    awdb_state st;
    for (int i = 0; i < 4; i++) {
        awdb_key k = key(20 + i, -60);
        CHECK(awdb_submit(db, &k, &st, &err) == 0);
    }
    pid_t pid = fork();
    if (pid == 0) {
        /* The builder to be killed: slow builds, two at a time. */
        test_engine te = te_init(2.0);
        awdb *dbc = awdb_open(dir, NULL, &err);
        run_builder(dbc, &te, 2, &err);
        _exit(0);
    }
    /* Wait until it is mid-build: requests in running/ and their
     * temporaries in fields/ (without one, the clean-up checked below would
     * have nothing to clean). */
    for (int t = 0; t < 500 && (count(dir, "running", ".req") < 2 || count_tmp(dir, "fields") < 2); t++)
        usleep(10000);
    usleep(300000);
    int running_before = count(dir, "running", ".req"), tmp_before = count_tmp(dir, "fields");
    printf("kill: %d builds running, %d temporaries in fields/ before SIGKILL\n", running_before, tmp_before);
    CHECK(running_before == 2 && tmp_before == 2);
    /* mid-build: nothing committed yet (count's loud temporaries taken out) */
    CHECK(count(dir, "fields", ".sum") - 1000 * tmp_before == 0);
    CHECK(awdb_builder_alive(db) == 1);
    /* A second builder on the same database is refused, naming the first. */
    test_engine te2 = te_init(0);
    char want[64];
    snprintf(want, sizeof want, "another builder (pid %ld)", (long)pid);
    CHECK(run_builder(db, &te2, 1, &err) < 0 && strstr(err.msg, want) != NULL);
    CHECK(te2.builds == 0);
    kill(pid, SIGKILL);
    int ws;
    waitpid(pid, &ws, 0);
    CHECK(WIFSIGNALED(ws));
    CHECK(awdb_builder_alive(db) == 0); /* the kernel dropped the dead builder's lock */
    CHECK(count_tmp(dir, "fields") == tmp_before); /* the dead builder's temporaries stay until a restart */
    /* Restart: interrupted builds are requeued, temporaries removed before
     * any build starts (one job: the first build finds none, not even the
     * other killed job's, which no rebuild of its own would remove first),
     * and the queue finishes; every field's checksum holds. */
    te2.db_dir = dir;
    CHECK(run_builder(db, &te2, 1, &err) == 0);
    CHECK(te2.builds == 4 && te2.stray_at_start == 0);
    awdb *fresh = awdb_open(dir, NULL, &err);
    for (int i = 0; i < 4; i++) {
        awdb_key k = key(20 + i, -60);
        awdb_key_canon(&k, &err);
        CHECK(awdb_query(fresh, &k, NULL, 0) == AWDB_READY);
    }
    CHECK(count(dir, "running", ".req") == 0 && count(dir, "queue", ".req") == 0);
    CHECK(count(dir, "fields", ".part") == 0 && count(dir, "fields", ".h5") < 1000 && count_tmp(dir, "fields") == 0);
    awdb_close(fresh);
    awdb_close(db);
}

/* SIGTERM mid-build: the build is abandoned, not failed and not committed,
 * its temporary removed; its request goes back to the front of a queue of
 * several, so that the restarted builder takes it first and the others in
 * the order they were asked for. */
static void test_term(const char *dir)
{
    core_err err = {0};
    awdb *db = awdb_open(dir, NULL, &err);
    enum { NT = 4 };
    awdb_key k[NT];
    char first[200];
    for (int i = 0; i < NT; i++) {
        k[i] = key(30 + i, 90);
        CHECK(awdb_submit(db, &k[i], NULL, &err) == 0);
        CHECK(awdb_key_canon(&k[i], &err) == 0);
    }
    awdb_key_name(&k[0], first, sizeof first);
    pid_t pid = fork();
    if (pid == 0) {
        signal(SIGTERM, on_term);
        test_engine te = te_init(3.0);
        awdb *dbc = awdb_open(dir, NULL, &err);
        awdb_engine eng = {"test", te_build, &te, NULL};
        awdb_builder_opts o = {1, 0, 0.01, NULL, NULL, NULL, NULL, 0.0};
        int rc = awdb_builder_run(dbc, &eng, &o, &term_flag, &err);
        awdb_close(dbc);
        _exit(rc == 0 ? 0 : 3);
    }
    char run[1400];
    snprintf(run, sizeof run, "%s/running/%s.req", dir, first);
    for (int t = 0; t < 500 && (access(run, F_OK) != 0 || count_tmp(dir, "fields") == 0); t++)
        usleep(10000);
    usleep(200000);
    /* mid-build of the first request: its claim and its temporary, the
     * other requests still queued */
    int tmp_before = count_tmp(dir, "fields");
    CHECK(access(run, F_OK) == 0 && tmp_before == 1 && count(dir, "queue", ".req") == NT - 1);
    kill(pid, SIGTERM);
    int ws;
    waitpid(pid, &ws, 0);
    CHECK(WIFEXITED(ws) && WEXITSTATUS(ws) == 0);
    awdb *fresh = awdb_open(dir, NULL, &err);
    CHECK(awdb_query(fresh, &k[0], NULL, 0) == AWDB_QUEUED);
    CHECK(count(dir, "running", ".req") == 0 && count(dir, "queue", ".req") == NT);
    CHECK(count(dir, "fields", ".h5") == 0 && count(dir, "failed", ".txt") == 0 && count_tmp(dir, "fields") == 0);
    CHECK(queue_first_is(dir, first));
    /* the restarted builder: the interrupted request first, then the rest
     * in submission order */
    test_engine te = te_init(0);
    CHECK(run_builder(fresh, &te, 1, &err) == 0);
    printf("term: %d temporary before SIGTERM; restart order (cm/s)", tmp_before);
    for (int i = 0; i < te.norder; i++)
        printf(" %d", te.order_cmps[i]);
    printf("\n");
    CHECK(te.norder == NT);
    for (int i = 0; i < NT && i < te.norder; i++)
        CHECK(te.order_cmps[i] == (int)(k[i].wod_speed_mps * 100 + 0.5));
    for (int i = 0; i < NT; i++)
        CHECK(awdb_query(fresh, &k[i], NULL, 0) == AWDB_READY);
    awdb_close(fresh);
    awdb_close(db);
}

/* An engine that makes some fields from others (the embedded engine's
 * mirror images): here every green wind (direction > 0) is made from the
 * red one of the same speed. The builder must hold such a request back
 * while its source runs or is queued ahead, so that with two jobs the pair
 * costs one build and the second build finds its source READY; a request
 * queued before its source is not held (nothing would build the source
 * first), and a request whose source is absent is built alone. */
typedef struct source_engine {
    test_engine te;
    awdb *db;
    int green_builds, green_saw_source;
    char order[8][16];
    int norder;
} source_engine;

static int se_source(void *user, const awdb_key *k, awdb_key *src)
{
    (void)user;
    if (!(k->wod_dir_rad > 1e-9))
        return 0;
    *src = *k;
    src->wod_dir_rad = -k->wod_dir_rad;
    core_err err = {0};
    return awdb_key_canon(src, &err) == 0;
}

static int se_build(void *user, const awdb_key *k, const char *warm, const char *out, awdb_progress_fn progress,
                    void *pu, core_err *err)
{
    source_engine *se = user;
    awdb_key src;
    if (se_source(se, k, &src)) {
        se->green_builds++;
        se->green_saw_source += awdb_query(se->db, &src, NULL, 0) == AWDB_READY;
    }
    if (se->norder < 8)
        snprintf(se->order[se->norder++], sizeof se->order[0], "%+.0f@%.0f%s", k->wod_dir_rad * CORE_RAD_TO_DEG,
                 k->wod_speed_mps, k->grid == CORE_GRID_QUICK ? "q" : "");
    return te_build(&se->te, k, warm, out, progress, pu, err);
}

static void test_source(const char *dir)
{
    core_err err = {0};
    awdb *db = awdb_open(dir, NULL, &err);
    CHECK(db != NULL);
    if (!db)
        return;
    source_engine se;
    memset(&se, 0, sizeof se);
    se.te.fail_speed_cmps = -1;
    se.te.sleep_s = 0.2; /* long enough for two jobs to overlap */
    se.db = db;
    /* red 30, then green 30 (held: its source is queued ahead), head (free) */
    awdb_key r30 = key(10, -30), g30 = key(10, 30), h = key(10, 0);
    CHECK(awdb_submit(db, &r30, NULL, &err) == 0);
    CHECK(awdb_submit(db, &g30, NULL, &err) == 0);
    CHECK(awdb_submit(db, &h, NULL, &err) == 0);
    /* green 60 before red 60: not held, built alone */
    awdb_key g60 = key(10, 60), r60 = key(10, -60);
    CHECK(awdb_submit(db, &g60, NULL, &err) == 0);
    CHECK(awdb_submit(db, &r60, NULL, &err) == 0);
    awdb_engine eng = {"test-source", se_build, &se, se_source};
    awdb_builder_opts o = {2, 1, 0.01, NULL, NULL, NULL, NULL, 0.0};
    CHECK(awdb_builder_run(db, &eng, &o, &no_stop, &err) == 0);
    printf("source: build order");
    for (int i = 0; i < se.norder; i++)
        printf(" %s", se.order[i]);
    printf("; green builds %d, %d of them with the red source ready\n", se.green_builds, se.green_saw_source);
    CHECK(se.te.builds == 5);
    CHECK(se.green_builds == 2);
    /* green 30 waited for red 30; green 60 (queued first) did not wait */
    CHECK(se.green_saw_source == 1);
    /* the first two jobs: red 30 and the head wind (in either order) */
    CHECK(se.norder == 5 && ((!strcmp(se.order[0], "-30@10") && !strcmp(se.order[1], "+0@10")) ||
                             (!strcmp(se.order[1], "-30@10") && !strcmp(se.order[0], "+0@10"))));
    CHECK(count(dir, "fields", ".h5") == 5 && count(dir, "queue", ".req") == 0);
    awdb_close(db);
}

/* The builder's order (awdb_builder_run): a mirror image whose source is
 * ready at once, then what a live process waits for (waiting/NAME.PID;
 * the source of a waited mirror with it), then the rest in submission
 * order, a dead process's mark counting for nothing (and removed). */
static void test_priority(const char *dir)
{
    core_err err = {0};
    awdb *db = awdb_open(dir, NULL, &err);
    CHECK(db != NULL);
    if (!db)
        return;
    source_engine se;
    memset(&se, 0, sizeof se);
    se.te.fail_speed_cmps = -1;
    se.db = db;
    awdb_engine eng = {"test-source", se_build, &se, se_source};
    awdb_builder_opts o = {1, 1, 0.01, NULL, NULL, NULL, NULL, 0.0};
    /* red 60 at 14 m/s first: its green image's source is then ready */
    awdb_key r60 = key(14, -60);
    CHECK(awdb_submit(db, &r60, NULL, &err) == 0);
    CHECK(awdb_builder_run(db, &eng, &o, &no_stop, &err) == 0);
    se.norder = 0;
    /* the queue in submission order: A (nobody waits), R (the source of G),
     * C (its waiter has ended), B (waited), G (waited; a mirror of R), D
     * (a mirror of the ready red 60) */
    awdb_key a = key(11, -30), r = key(15, -30), c = key(13, 0), b = key(12, 0), g = key(15, 30), d = key(14, 60);
    awdb_key *all[] = {&a, &r, &c, &b, &g, &d};
    for (int i = 0; i < 6; i++) {
        CHECK(awdb_submit(db, all[i], NULL, &err) == 0);
        struct timespec ts = {0, 2000000}; /* distinct submission times */
        nanosleep(&ts, NULL);
    }
    CHECK(awdb_wait_mark(db, &b, &err) == 0 && awdb_wait_mark(db, &g, &err) == 0);
    /* C's mark, by a process that has ended */
    pid_t kid = fork();
    if (kid == 0)
        _exit(0);
    CHECK(kid > 0 && waitpid(kid, NULL, 0) == kid);
    char cn[200], mark[1400];
    awdb_key cc = c;
    CHECK(awdb_key_canon(&cc, &err) == 0);
    awdb_key_name(&cc, cn, sizeof cn);
    snprintf(mark, sizeof mark, "%s/waiting/%s.%ld", dir, cn, (long)kid);
    FILE *f = fopen(mark, "w");
    CHECK(f != NULL);
    if (f)
        fclose(f);
    CHECK(awdb_builder_run(db, &eng, &o, &no_stop, &err) == 0);
    printf("priority: build order");
    for (int i = 0; i < se.norder; i++)
        printf(" %s", se.order[i]);
    printf("\n");
    static const char *want[] = {"+60@14", "-30@15", "+30@15", "+0@12", "-30@11", "+0@13"};
    CHECK(se.norder == 6);
    for (int i = 0; i < 6 && i < se.norder; i++)
        CHECK(!strcmp(se.order[i], want[i]));
    CHECK(access(mark, F_OK) != 0); /* the dead process's mark removed */
    /* this process's marks stay until it takes them back */
    CHECK(count(dir, "waiting", "") == 2);
    awdb_wait_unmark(db, &b);
    awdb_wait_unmark(db, &g);
    CHECK(count(dir, "waiting", "") == 0);
    awdb_close(db);
}

/* A flight's levels: a coarse ship-only request waits while its own
 * wind's quick field is building (queued ahead), then starts from it; a
 * field of another wind is built beside the quick one meanwhile. */
static void test_levels(const char *dir)
{
    core_err err = {0};
    awdb *db = awdb_open(dir, NULL, &err);
    CHECK(db != NULL);
    if (!db)
        return;
    test_engine te = te_init(0.2);
    awdb_key q = key(10, 0), c, u = key(11, 0);
    q.rotor = u.rotor = CORE_ROTOR_OFF;
    q.grid = CORE_GRID_QUICK;
    c = q;
    c.grid = CORE_GRID_COARSE;
    CHECK(awdb_submit(db, &q, NULL, &err) == 0 && awdb_submit(db, &c, NULL, &err) == 0 &&
          awdb_submit(db, &u, NULL, &err) == 0);
    CHECK(run_builder(db, &te, 2, &err) == 0);
    char nq[200];
    CHECK(awdb_key_canon(&q, &err) == 0);
    awdb_key_name(&q, nq, sizeof nq);
    printf("levels: build order (cm/s) %d %d %d; the last from %s\n", te.order_cmps[0], te.order_cmps[1],
           te.order_cmps[2], te.last_warm[0] ? te.last_warm : "the inflow");
    CHECK(te.builds == 3 && te.norder == 3);
    /* quick and the other wind first (either order), the coarse one last, from the quick field */
    CHECK(te.order_cmps[0] + te.order_cmps[1] == 2100 && te.order_cmps[2] == 1000);
    CHECK(strstr(te.last_warm, nq) != NULL);
    /* a mirror image whose source is ready does not wait for its own
     * wind's quick field (it is made, not solved): the green coarse field
     * before the green quick one queued ahead of it (the builder's first
     * class) */
    source_engine se;
    memset(&se, 0, sizeof se);
    se.te.fail_speed_cmps = -1;
    se.db = db;
    awdb_engine eng = {"test-source", se_build, &se, se_source};
    awdb_builder_opts o = {1, 1, 0.01, NULL, NULL, NULL, NULL, 0.0};
    awdb_key r30 = key(12, -30), g30q, g30 = key(12, 30);
    r30.rotor = g30.rotor = CORE_ROTOR_OFF;
    g30q = g30;
    g30q.grid = CORE_GRID_QUICK;
    CHECK(awdb_submit(db, &r30, NULL, &err) == 0 && awdb_builder_run(db, &eng, &o, &no_stop, &err) == 0);
    se.norder = 0;
    CHECK(awdb_submit(db, &g30q, NULL, &err) == 0 && awdb_submit(db, &g30, NULL, &err) == 0);
    CHECK(awdb_builder_run(db, &eng, &o, &no_stop, &err) == 0);
    printf("levels: then %s %s\n", se.order[0], se.order[1]);
    CHECK(se.norder == 2 && !strcmp(se.order[0], "+30@12") && !strcmp(se.order[1], "+30@12q"));
    awdb_close(db);
}

/* The builder's restart clean-up removes temporaries only: not the fields
 * and requests of a ship whose name has ".part" or ".tmp" in it, and not a
 * request a live client is writing (FILE.tmpPID in queue/); a dead
 * process's temporary goes. */
static void test_recover(const char *dir)
{
    core_err err = {0};
    awdb *db = awdb_open(dir, NULL, &err);
    CHECK(db != NULL);
    if (!db)
        return;
    test_engine te = te_init(0);
    awdb_key k1 = key(10, 0), k2 = key(12, 0);
    snprintf(k1.ship, sizeof k1.ship, "LHA.partial");
    snprintf(k2.ship, sizeof k2.ship, "LHA.tmp2");
    CHECK(awdb_submit(db, &k1, NULL, &err) == 0 && run_builder(db, &te, 1, &err) == 0);
    CHECK(awdb_key_canon(&k1, &err) == 0 && awdb_key_canon(&k2, &err) == 0);
    CHECK(awdb_query(db, &k1, NULL, 0) == AWDB_READY);
    CHECK(awdb_submit(db, &k2, NULL, &err) == 0);
    char live[1200], dead[1200], ftmp[1200];
    snprintf(live, sizeof live, "%s/queue/00000003-X.req.tmp%ld", dir, (long)getpid());
    pid_t pid = fork();
    if (pid == 0)
        _exit(0);
    waitpid(pid, NULL, 0);
    snprintf(dead, sizeof dead, "%s/queue/00000004-Y.req.tmp%ld", dir, (long)pid);
    snprintf(ftmp, sizeof ftmp, "%s/fields/.tmp-Z.h5", dir);
    const char *tmps[] = {live, dead, ftmp};
    for (int i = 0; i < 3; i++) {
        FILE *f = fopen(tmps[i], "w");
        CHECK(f != NULL);
        if (f)
            fclose(f);
    }
    CHECK(run_builder(db, &te, 1, &err) == 0);
    awdb *fresh = awdb_open(dir, NULL, &err);
    CHECK(awdb_query(fresh, &k1, NULL, 0) == AWDB_READY);
    CHECK(awdb_query(fresh, &k2, NULL, 0) == AWDB_READY && te.builds == 2);
    CHECK(access(live, F_OK) == 0 && access(dead, F_OK) != 0 && access(ftmp, F_OK) != 0);
    remove(live);
    awdb_close(fresh);
    awdb_close(db);
}

/* A client checking a field while a builder commits a new one over it (the
 * old file corrupt, the builder done and its running/ request gone by the
 * time the check ends) must not remove the new field. The check is held in
 * the middle with a FIFO standing for the old field file: the client's
 * checksum read waits on it while the "builder" renames the good file into
 * place and drops its request, then reads garbage. */
typedef struct reader_arg {
    awdb *db;
    awdb_key key;
    awdb_state st;
} reader_arg;

static void *reader(void *p)
{
    reader_arg *a = p;
    a->st = awdb_query(a->db, &a->key, NULL, 0);
    return NULL;
}

static void test_commit_race(const char *dir)
{
    core_err err = {0};
    awdb *db = awdb_open(dir, NULL, &err);
    CHECK(db != NULL);
    if (!db)
        return;
    test_engine te = te_init(0);
    awdb_key k = key(11, 0);
    CHECK(awdb_submit(db, &k, NULL, &err) == 0 && run_builder(db, &te, 1, &err) == 0);
    CHECK(awdb_key_canon(&k, &err) == 0);
    char h5[1100], aside[1100], run[1100], name[200];
    CHECK(awdb_query(db, &k, h5, sizeof h5) == AWDB_READY);
    awdb_key_name(&k, name, sizeof name);
    snprintf(aside, sizeof aside, "%s/aside.h5", dir);
    snprintf(run, sizeof run, "%s/running/%s.req", dir, name);
    CHECK(rename(h5, aside) == 0 && mkfifo(h5, 0600) == 0);
    FILE *f = fopen(run, "w"); /* the builder's claim */
    CHECK(f != NULL);
    if (f)
        fclose(f);
    reader_arg a = {awdb_open(dir, NULL, &err), k, AWDB_ABSENT};
    pthread_t th;
    CHECK(a.db && pthread_create(&th, NULL, reader, &a) == 0);
    int fd = -1;
    for (int t = 0; t < 500 && fd < 0; t++) { /* until the client opened the field */
        fd = open(h5, O_WRONLY | O_NONBLOCK);
        if (fd < 0)
            usleep(10000);
    }
    CHECK(fd >= 0);
    /* the commit: the new field in place, the claim dropped */
    CHECK(rename(aside, h5) == 0 && remove(run) == 0);
    if (fd >= 0) {
        CHECK(write(fd, "garbage", 7) == 7);
        close(fd);
    }
    pthread_join(th, NULL);
    CHECK(a.st == AWDB_READY);
    awdb *fresh = awdb_open(dir, NULL, &err);
    CHECK(awdb_query(fresh, &k, NULL, 0) == AWDB_READY);
    awdb_close(fresh);
    awdb_close(a.db);
    awdb_close(db);
}

/* A check that cannot run (no file descriptor left) is no evidence of
 * corruption: the field stays. */
static void test_check_fails(const char *dir)
{
    core_err err = {0};
    awdb *db = awdb_open(dir, NULL, &err);
    CHECK(db != NULL);
    if (!db)
        return;
    test_engine te = te_init(0);
    awdb_key k = key(13, 0);
    CHECK(awdb_submit(db, &k, NULL, &err) == 0 && run_builder(db, &te, 1, &err) == 0);
    CHECK(awdb_key_canon(&k, &err) == 0);
    pid_t pid = fork();
    if (pid == 0) {
        awdb *c = awdb_open(dir, NULL, &err); /* no verification cache */
        struct rlimit rl;
        getrlimit(RLIMIT_NOFILE, &rl);
        rl.rlim_cur = 64;
        setrlimit(RLIMIT_NOFILE, &rl);
        while (open("/dev/null", O_RDONLY) >= 0)
            ;
        awdb_state st = c ? awdb_query(c, &k, NULL, 0) : AWDB_READY;
        _exit(st == AWDB_READY ? 1 : 0); /* READY cannot have been checked */
    }
    int ws;
    waitpid(pid, &ws, 0);
    CHECK(WIFEXITED(ws) && WEXITSTATUS(ws) == 0);
    awdb *fresh = awdb_open(dir, NULL, &err);
    CHECK(awdb_query(fresh, &k, NULL, 0) == AWDB_READY);
    awdb_close(fresh);
    awdb_close(db);
}

/* A client's probe (awdb_builder_alive) holds builder.lock for an instant,
 * shared: another probe at that instant sees no builder, and a builder
 * starting then waits it out instead of refusing to run. */
static void test_probe(const char *dir)
{
    core_err err = {0};
    awdb *db = awdb_open(dir, NULL, &err);
    CHECK(db != NULL);
    if (!db)
        return;
    char lockp[1100];
    snprintf(lockp, sizeof lockp, "%s/builder.lock", dir);
    int pfd[2];
    CHECK(pipe(pfd) == 0);
    pid_t pid = fork();
    if (pid == 0) {
        int fd = open(lockp, O_RDONLY | O_CREAT, 0666);
        char c = fd >= 0 && flock(fd, LOCK_SH) == 0 ? 'y' : 'n';
        if (write(pfd[1], &c, 1) != 1)
            _exit(1);
        usleep(300000);
        _exit(0);
    }
    char c = 0;
    CHECK(read(pfd[0], &c, 1) == 1 && c == 'y');
    close(pfd[0]);
    close(pfd[1]);
    CHECK(awdb_builder_alive(db) == 0);
    test_engine te = te_init(0);
    awdb_key k = key(9, 0);
    CHECK(awdb_submit(db, &k, NULL, &err) == 0);
    CHECK(run_builder(db, &te, 1, &err) == 0 && te.builds == 1);
    waitpid(pid, NULL, 0);
    awdb_close(db);
}

/* A request that cannot be claimed (here running/ is a file, so link()
 * fails with ENOTDIR; on a file system without hard links it would be
 * EPERM) goes to failed/ saying why; before, it was skipped on every scan
 * and an --exit-when-idle builder never stopped. */
static void test_unclaimable(const char *dir)
{
    core_err err = {0};
    awdb *db = awdb_open(dir, NULL, &err);
    CHECK(db != NULL);
    if (!db)
        return;
    awdb_key k = key(9, 0);
    CHECK(awdb_submit(db, &k, NULL, &err) == 0);
    char run[1100];
    snprintf(run, sizeof run, "%s/running", dir);
    CHECK(rmdir(run) == 0);
    FILE *f = fopen(run, "w");
    CHECK(f != NULL);
    if (f)
        fclose(f);
    test_engine te = te_init(0);
    CHECK(run_builder(db, &te, 1, &err) == 0); /* returns: the queue is empty */
    CHECK(te.builds == 0 && count(dir, "queue", ".req") == 0 && count(dir, "failed", ".txt") == 1);
    char name[256], failed[1400], text[1400] = "";
    awdb_key c = k;
    CHECK(awdb_key_canon(&c, &err) == 0);
    awdb_key_name(&c, name, sizeof name);
    snprintf(failed, sizeof failed, "%s/failed/%s.txt", dir, name);
    f = fopen(failed, "r");
    CHECK(f != NULL);
    if (f) {
        CHECK(fgets(text, sizeof text, f) != NULL);
        fclose(f);
    }
    CHECK(strstr(text, "cannot claim the request") != NULL);
    remove(run);
    awdb_close(db);
}

/* The builder's progress files (running/NAME.prog) and awdb_progress_read.
 * An engine of PROG_MAX iterations, 25 ms each, reporting frac = iteration
 * / cap as the embedded engine does; three requests built one at a time
 * with a progress file written at most every 20 ms. A reader races the
 * writer: each read of the file finds it whole or finds none, and every
 * awdb_progress_read is sane (counts consistent, iteration within the cap,
 * fraction = iteration / cap, time left bounded); after the builds no
 * progress file is left. A restarted builder removes stale progress files,
 * and a torn one (from before a power cut) reads as none. */
#define PROG_MAX 40
static int pe_build(void *user, const awdb_key *k, const char *warm, const char *out, awdb_progress_fn progress,
                    void *pu, core_err *err)
{
    (void)user;
    (void)warm;
    FILE *f = fopen(out, "w");
    if (!f)
        return core_err_set(err, -1, "%s: cannot write", out);
    fprintf(f, "%s %.2f\n", k->ship, k->wod_speed_mps);
    fclose(f);
    for (int i = 1; i <= PROG_MAX; i++) {
        struct timespec ts = {0, 25000000};
        nanosleep(&ts, NULL);
        if (progress(pu, (double)i / PROG_MAX, 1e-2 / i, i))
            break;
    }
    return 0;
}

typedef struct prog_thread {
    awdb *db;
    int rc;
    core_err err;
} prog_thread;

static void *prog_builder(void *arg)
{
    prog_thread *t = arg;
    awdb_engine eng = {"progress", pe_build, NULL, NULL};
    awdb_builder_opts o = {1, 1, 0.01, NULL, NULL, NULL, NULL, 0.02};
    t->rc = awdb_builder_run(t->db, &eng, &o, &no_stop, &t->err);
    return NULL;
}

/* A raw read of a progress file: 1 whole, 0 absent, -1 anything else. */
static int read_raw_progress(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return errno == ENOENT ? 0 : -1;
    char text[1024];
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = '\0';
    return !strncmp(text, "[progress]\n", 11) && strstr(text, "\nleft_s = ") && text[n - 1] == '\n' ? 1 : -1;
}

static void test_progress(const char *dir)
{
    core_err err = {0};
    awdb *db = awdb_open(dir, NULL, &err);
    CHECK(db != NULL);
    if (!db)
        return;
    awdb_progress pr;
    CHECK(awdb_progress_read(db, &pr, &err) == 0);
    CHECK(pr.ready == 0 && pr.queued == 0 && pr.running == 0 && pr.n_runs == 0 && pr.builder_alive == 0);
    awdb_key k[3] = {key(12, 0), key(13, 0), key(14, 0)};
    char names[3][200], progp[3][1400];
    for (int i = 0; i < 3; i++) {
        CHECK(awdb_submit(db, &k[i], NULL, &err) == 0);
        CHECK(awdb_key_canon(&k[i], &err) == 0);
        awdb_key_name(&k[i], names[i], sizeof names[i]);
        snprintf(progp[i], sizeof progp[i], "%s/running/%s.prog", dir, names[i]);
    }
    CHECK(awdb_progress_read(db, &pr, &err) == 0 && pr.queued == 3 && pr.running == 0 && pr.ready == 0);
    prog_thread t = {awdb_open(dir, NULL, &err), 0, {{0}, 0}};
    pthread_t th;
    CHECK(t.db && pthread_create(&th, NULL, prog_builder, &t) == 0);
    int whole = 0, torn = 0, reads = 0, insane = 0, seen_first = 0, seen_left = 0, last_ready = 0, last_queued = 3,
        order = 0, seen_which[3] = {0, 0, 0};
    for (int loop = 0; loop < 200000; loop++) {
        for (int i = 0; i < 3; i++) {
            int r = read_raw_progress(progp[i]);
            whole += r == 1;
            torn += r < 0;
        }
        if (awdb_progress_read(db, &pr, &err) != 0) {
            insane++;
            break;
        }
        reads++;
        /* a request may count twice (the claim links before it unlinks, a
         * commit renames its .sum before the claim goes, and the folders
         * are read one after the other), never not at all */
        if (pr.ready + pr.queued + pr.running < 3 || pr.n_runs != pr.running || pr.ready > 3 || pr.queued > 3)
            insane++;
        if (pr.ready < last_ready || pr.queued > last_queued)
            order++;
        last_ready = pr.ready;
        last_queued = pr.queued;
        for (int r = 0; r < pr.n_runs; r++) {
            const awdb_run_progress *p = &pr.runs[r];
            int which = -1;
            for (int i = 0; i < 3; i++)
                if (!strcmp(p->name, names[i]))
                    which = i;
            if (which < 0)
                insane++;
            if (!p->have)
                continue;
            if (which >= 0)
                seen_which[which] = 1;
            if (p->iteration < 0 || p->iteration > PROG_MAX || p->elapsed_s < 0 || p->elapsed_s > 60 ||
                p->left_s > 10 || (p->left_s < 0 && p->left_s != -1.0) || fabs(p->frac - (double)p->iteration / PROG_MAX) > 1e-6)
                insane++;
            if (p->iteration > 0 && (p->max_iterations != PROG_MAX || !(p->residual > 0)))
                insane++;
            if (p->iteration == 0 && p->left_s != -1.0)
                insane++;
            if (p->iteration > 0 && pr.queued >= 1 && awdb_progress_find(&pr, p->name) == p)
                seen_first = 1;
            if (p->iteration > 2 && p->left_s >= 0)
                seen_left = 1;
        }
        if (pr.ready == 3 && pr.running == 0)
            break;
        usleep(500);
    }
    pthread_join(th, NULL);
    CHECK(t.rc == 0);
    if (torn || insane || order)
        fprintf(stderr, "  progress: %d reads, %d whole files, %d torn, %d insane, %d out of order\n", reads, whole, torn,
                insane, order);
    CHECK(torn == 0 && insane == 0 && order == 0);
    CHECK(whole > 10 && seen_first && seen_left);
    CHECK(seen_which[0] && seen_which[1] && seen_which[2]);
    /* after the builds: every field ready, nothing running, no progress file */
    CHECK(awdb_progress_read(db, &pr, &err) == 0);
    CHECK(pr.ready == 3 && pr.queued == 0 && pr.running == 0 && pr.n_runs == 0 && pr.builder_alive == 0);
    CHECK(count(dir, "running", ".prog") == 0 && count(dir, "running", "") == 0);
    CHECK(awdb_progress_find(&pr, names[0]) == NULL);
    /* A builder killed mid-build leaves running/NAME.req with a progress
     * file, here torn (as after a power cut), and a stray temporary: the
     * torn file reads as no progress; a restart requeues the request and
     * removes both. */
    awdb_key kk = key(15, 0);
    CHECK(awdb_key_canon(&kk, &err) == 0);
    char kname[200], req[1400], text[AWDB_KEY_TEXT];
    awdb_key_name(&kk, kname, sizeof kname);
    snprintf(req, sizeof req, "%s/running/%s.req", dir, kname);
    awdb_key_format(&kk, text, sizeof text);
    FILE *f = fopen(req, "w");
    CHECK(f != NULL);
    if (f) {
        fputs(text, f);
        fclose(f);
    }
    char pp[1400], ptmp[1500], orphan[1400];
    snprintf(pp, sizeof pp, "%s/running/%s.prog", dir, kname);
    snprintf(ptmp, sizeof ptmp, "%s.tmp%ld", pp, (long)getpid());
    snprintf(orphan, sizeof orphan, "%s/running/gone.prog", dir);
    f = fopen(pp, "w");
    if (f) {
        fputs("[progress]\niteration = 7\nmax_iter", f);
        fclose(f);
    }
    f = fopen(ptmp, "w");
    if (f)
        fclose(f);
    f = fopen(orphan, "w");
    if (f) {
        fputs("[progress]\niteration = 1\nmax_iterations = 9\nresidual = 1\nfraction = 0.1\nelapsed_s = 1\nleft_s = 8\n", f);
        fclose(f);
    }
    CHECK(awdb_progress_read(db, &pr, &err) == 0);
    CHECK(pr.running == 1 && pr.n_runs == 1 && !strcmp(pr.runs[0].name, kname) && pr.runs[0].have == 0 &&
          pr.runs[0].left_s == -1.0);
    t.rc = -1;
    CHECK(pthread_create(&th, NULL, prog_builder, &t) == 0);
    pthread_join(th, NULL);
    CHECK(t.rc == 0);
    CHECK(access(pp, F_OK) != 0 && access(ptmp, F_OK) != 0 && access(orphan, F_OK) != 0);
    CHECK(awdb_progress_read(db, &pr, &err) == 0 && pr.ready == 4 && pr.queued == 0 && pr.running == 0);
    awdb_close(t.db);
    awdb_close(db);
}

/* The embedded CFD engine through the builder, once: a coarse SFS2
 * ship-only field, EMB_ITER iterations (this checks the path, not the
 * flow). The engine, wrapped, is seen to write its field to the builder's
 * temporary (fields/.tmp-NAME.h5, beside the final name so that the commit
 * is a rename); after the commit the field is READY (its checksum holds)
 * and reads back as a field, and neither the temporary nor the writer's
 * XDMF side file (.tmp-NAME.xmf) is left. */
#define EMB_ITER 3
typedef struct watch_engine {
    awdb_engine real;
    const char *dir;
    int builds, tmp_named, tmp_written;
    long tmp_bytes;
} watch_engine;

static int watch_build(void *user, const awdb_key *k, const char *warm, const char *out, awdb_progress_fn progress,
                       void *pu, core_err *err)
{
    watch_engine *w = user;
    char want[1200];
    snprintf(want, sizeof want, "%s/fields/.tmp-", w->dir);
    w->builds++;
    w->tmp_named += !strncmp(out, want, strlen(want));
    int rc = w->real.build(w->real.user, k, warm, out, progress, pu, err);
    struct stat sb;
    if (rc == 0 && stat(out, &sb) == 0 && sb.st_size > 0) {
        w->tmp_written++;
        w->tmp_bytes = (long)sb.st_size;
    }
    return rc;
}

static void test_embedded(const char *dir)
{
    core_err err = {0};
    core_log log = {NULL, NULL, CORE_LOG_ERROR};
    awdb *db = awdb_open(dir, NULL, &err);
    awdb_embedded *e = awdb_embedded_create("scenarios/ships", EMB_ITER, 1, &log, &err);
    CHECK(db && e);
    if (!db || !e) {
        fprintf(stderr, "  embedded: %s\n", err.msg);
        awdb_embedded_destroy(e);
        awdb_close(db);
        return;
    }
    awdb_embedded_set_db(e, db);
    watch_engine w;
    memset(&w, 0, sizeof w);
    w.dir = dir;
    awdb_embedded_engine(e, &w.real);
    awdb_engine eng = {"embedded-watched", watch_build, &w, NULL};
    awdb_key k = key(10, 0);
    snprintf(k.ship, sizeof k.ship, "SFS2");
    k.rotor = CORE_ROTOR_OFF;
    k.thrust_N = 0.0;
    CHECK(awdb_submit(db, &k, NULL, &err) == 0 && awdb_key_canon(&k, &err) == 0);
    awdb_builder_opts o = {1, 1, 0.01, NULL, NULL, NULL, NULL, 0.0};
    CHECK(awdb_builder_run(db, &eng, &o, &no_stop, &err) == 0);
    printf("embedded: %d build(s), the field written to its temporary (%ld bytes), then renamed\n", w.builds,
           w.tmp_bytes);
    CHECK(w.builds == 1 && w.tmp_named == 1 && w.tmp_written == 1 && w.tmp_bytes > 0);
    char path[1200];
    CHECK(awdb_query(db, &k, path, sizeof path) == AWDB_READY);
    cfd_field *f = cfd_field_load(path, &err);
    CHECK(f != NULL);
    if (!f)
        fprintf(stderr, "  embedded: %s\n", err.msg);
    cfd_field_destroy(f);
    CHECK(count_tmp(dir, "fields") == 0 && count(dir, "fields", ".xmf") == 0 && count(dir, "fields", ".h5") == 1);
    CHECK(count(dir, "running", "") == 0 && count(dir, "queue", ".req") == 0 && count(dir, "failed", ".txt") == 0);
    awdb_embedded_destroy(e);
    awdb_close(db);
}

/* A ships folder whose file paths do not fit the loader's buffer: refused
 * by name (the path was cut, and the ship then "not found" later). */
static void test_long_ships_path(const char *dir)
{
    char p[1400];
    int n = snprintf(p, sizeof p, "%s", dir);
    CHECK(mkdir(p, 0777) == 0);
    for (int i = 0; i < 5; i++) {
        n += snprintf(p + n, sizeof p - n, "/%0200d", i);
        CHECK(mkdir(p, 0777) == 0);
    }
    char f[1500];
    snprintf(f, sizeof f, "%s/x.ini", p);
    FILE *fp = fopen(f, "w");
    CHECK(fp != NULL);
    if (fp)
        fclose(fp);
    core_err err = {0};
    core_log log = {NULL, NULL, CORE_LOG_ERROR};
    awdb_embedded *e = awdb_embedded_create(p, 10, 1, &log, &err);
    CHECK(e == NULL && strstr(err.msg, "path longer") != NULL);
    if (!strstr(err.msg, "path longer"))
        fprintf(stderr, "  long ships path: %s\n", err.msg);
    awdb_embedded_destroy(e);
}

/* The database's engine file: the first claim writes it, a second engine
 * is refused by name, fields from before the file are the embedded
 * engine's, a damaged file is named. */
static void test_engine_mark(const char *dir)
{
    core_err err = {0};
    awdb *db = awdb_open(dir, NULL, &err);
    CHECK(db != NULL);
    if (!db)
        return;
    CHECK(awdb_engine_claim(db, "openfoam", &err) == 0);
    CHECK(awdb_engine_claim(db, "openfoam", &err) == 0);
    CHECK(awdb_engine_claim(db, "embedded", &err) < 0);
    CHECK(strstr(err.msg, "openfoam engine's fields") && strstr(err.msg, "embedded engine's"));
    CHECK(awdb_engine_claim(db, "Bad Name", &err) < 0);
    CHECK(count_tmp(dir, "") == 0);
    char p[256];
    snprintf(p, sizeof p, "%s/engine", dir);
    FILE *f = fopen(p, "w");
    CHECK(f != NULL);
    if (f) {
        fputs("open foam\n", f);
        fclose(f);
    }
    CHECK(awdb_engine_claim(db, "openfoam", &err) < 0);
    CHECK(strstr(err.msg, "/engine: expected one line naming the engine") != NULL);
    /* a database with a field and no engine file: the embedded engine's */
    remove(p);
    snprintf(p, sizeof p, "%s/fields/old.h5", dir);
    f = fopen(p, "w");
    if (f)
        fclose(f);
    CHECK(awdb_engine_claim(db, "openfoam", &err) < 0);
    CHECK(strstr(err.msg, "holds the embedded engine's fields") != NULL);
    CHECK(awdb_engine_claim(db, "embedded", &err) == 0);
    awdb_close(db);
}

int main(void)
{
    char dir[] = "/tmp/disim_awdb_XXXXXX";
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    test_keys();
    test_crc(dir);
    char d1[64], d2[64];
    snprintf(d1, sizeof d1, "%s/db1", dir);
    snprintf(d2, sizeof d2, "%s/db2", dir);
    test_flow(d1);
    test_kill(d2);
    char d3[64];
    snprintf(d3, sizeof d3, "%s/db3", dir);
    test_term(d3);
    char d4[64];
    snprintf(d4, sizeof d4, "%s/db4", dir);
    test_source(d4);
    snprintf(d4, sizeof d4, "%s/db4p", dir);
    test_priority(d4);
    snprintf(d4, sizeof d4, "%s/db4l", dir);
    test_levels(d4);
    char d5[64];
    snprintf(d5, sizeof d5, "%s/db5", dir);
    test_recover(d5);
    snprintf(d5, sizeof d5, "%s/db6", dir);
    test_commit_race(d5);
    snprintf(d5, sizeof d5, "%s/db7", dir);
    test_check_fails(d5);
    snprintf(d5, sizeof d5, "%s/db8", dir);
    test_probe(d5);
    snprintf(d5, sizeof d5, "%s/db9", dir);
    test_unclaimable(d5);
    snprintf(d5, sizeof d5, "%s/db10", dir);
    test_progress(d5);
    snprintf(d5, sizeof d5, "%s/db11", dir);
    test_embedded(d5);
    snprintf(d5, sizeof d5, "%s/ships", dir);
    test_long_ships_path(d5);
    snprintf(d5, sizeof d5, "%s/db12", dir);
    test_engine_mark(d5);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "cannot remove %s\n", dir);
    return check_done("test_awdb");
}
