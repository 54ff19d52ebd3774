/*
 * awdb.h -- the airwake database and its background builder.
 *
 * A database is a folder:
 *   fields/NAME.h5      finished fields, each with NAME.sum (size and CRC-64
 *                       of the field file); an entry counts only when both are
 *                       there and agree, so a torn write is never read
 *   queue/SEQ-NAME.req  requests waiting (one small INI file each)
 *   running/NAME.req    requests a builder has claimed (rename is the claim)
 *   running/NAME.prog   the progress of a claimed request's build (about once
 *                       a second; awdb_progress_read), removed when it ends
 *   failed/NAME.txt     requests that failed, with the reason
 *   waiting/NAME.PID    a running process waits for NAME (awdb_wait_mark);
 *                       the builder serves those first (awdb_builder_run
 *                       has the order) and removes the marks of processes
 *                       that have ended
 *   builder.lock        flock()ed by the one running builder
 *   engine              the engine whose fields it holds (awdb_engine_claim)
 * Every file is written to a temporary name and renamed into place, so a
 * crash or kill at any instant leaves the database consistent; a restarted
 * builder returns running/ requests to the queue and removes stray
 * temporaries and progress files. A progress file is replaced by rename
 * too, so a reader finds a whole one or none. Fields are keyed by ship, aircraft, WOD, rotor mode, thrust,
 * rotor station and grid (awdb_key). Several clients (disim shol, disim
 * airwake --queue, LCM requests relayed by the builder) share one database;
 * a key is built once however many ask for it.
 */
#ifndef DISIM_AWDB_H
#define DISIM_AWDB_H

#include "core.h"

#include <signal.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The loaded-disk table of a key: radial stations x azimuths. */
#define AWDB_LOAD_NR 8
#define AWDB_LOAD_NPSI 12

/* What a field is. Values are rounded by awdb_key_canon (speed 0.01 m/s,
 * direction 0.01 deg, thrust 1 N, station and radius 1 cm, shaft tilt
 * 0.1 deg) so that equal requests compare equal. */
typedef struct awdb_key {
    char ship[96];        /* ship name; "NAME.isolated": the same case with the ship cells open */
    char aircraft[64];     /* "" for a ship-only field */
    double wod_speed_mps;
    double wod_dir_rad;
    core_rotor_mode rotor;
    double thrust_N;       /* 0 with the rotor off */
    double station_S_m[3]; /* rotor hub in S */
    double radius_m;       /* rotor radius */
    double shaft_pitch_rad, shaft_roll_rad; /* shaft tilt in S (0.1 deg resolution) */
    core_grid_level grid;
    /* > 0: the field covers the deck zone only (cfd_airwake_spec.zone; a
     * coupled point's coupled and isolated fields), its open faces set from
     * the ship-only field of the same ship, direction and grid at this
     * speed (m/s, 0.01), scaled to wod_speed_mps; that field must be in the
     * database before the zone is built. 0: the whole domain. Always 0 in
     * calm air. With the rotor off (the zone's own ship-only field, the
     * coupling's reference for what the zone changes) station_S_m and
     * radius_m still place the zone and the aircraft name stays. */
    double zone_ref_mps;
    /* rotor == CORE_ROTOR_LOADED: the blade loads of a trim (from the flight
     * model), as the CFD disk takes them: the pressure-jump shape
     * load[ipsi * AWDB_LOAD_NR + ir] at r/R = (ir + 0.5) / AWDB_LOAD_NR and
     * psi = 2 pi ipsi / AWDB_LOAD_NPSI from the tail in the rotation sense
     * (mean 1, rounded to 0.001), the tangential-force shape swirl[ir] (max 1,
     * 0.001), the shaft torque (10 N m), the root cut r/R (0.001) and the
     * sense. Zero for the other rotor modes. */
    double load[AWDB_LOAD_NR * AWDB_LOAD_NPSI];
    double swirl[AWDB_LOAD_NR];
    double torque_Nm;
    double root_cut;
    int ccw_from_above;    /* 1 counter-clockwise seen from above (UH-60A), 0 clockwise (SA365N) */
} awdb_key;

typedef enum {
    AWDB_ABSENT = 0,
    AWDB_QUEUED = 1,
    AWDB_RUNNING = 2,
    AWDB_READY = 3,
    AWDB_FAILED = 4,
} awdb_state;

const char *awdb_state_name(awdb_state s);

/* Round a key's values to their canonical resolution; checks names and
 * ranges: returns < 0 with err naming the field. */
int awdb_key_canon(awdb_key *key, core_err *err);
/* The boundary of a deck-zone key (zone_ref_mps > 0): the whole-domain
 * ship-only field of its ship, direction and grid at zone_ref_mps, the key
 * the engine reads and a client must have built first (not canonical). */
void awdb_key_zone_boundary(const awdb_key *zone, awdb_key *boundary);
/* File stem for a canonical key: readable parts and a 64-bit hash of all;
 * it fits in AWDB_NAME_MAX bytes (awdb_key_canon refuses longer names). */
#define AWDB_NAME_MAX 200
void awdb_key_name(const awdb_key *key, char *buf, size_t n);

typedef struct awdb awdb;

/* Open (creating the folders if needed). NULL with err on failure. */
awdb *awdb_open(const char *dir, const core_log *log, core_err *err);
void awdb_close(awdb *db);
/* A key does not name its engine, so a database holds one engine's
 * fields. Claim the database for engine ("embedded", "openfoam") when it
 * names none yet (one with fields but no engine file is the embedded
 * engine's), else check it: 0 when its fields are engine's, < 0 with err
 * naming both otherwise. Builders and the clients that ask for fields call
 * it once after awdb_open. */
int awdb_engine_claim(awdb *db, const char *engine, core_err *err);
const char *awdb_dir(const awdb *db);

/* State of a key. READY only after the field's checksum was verified; a
 * field whose checksum fails is removed (logged) and reported ABSENT, unless
 * a builder replaced it during the check (then the new one is checked); one
 * that cannot be checked now (no file descriptor left, an I/O error) is
 * kept and reported as if absent. With path != NULL, READY fills the
 * field's path. */
awdb_state awdb_query(awdb *db, const awdb_key *key, char *path, size_t n);
/* Ask for a key: if it is not READY, QUEUED or RUNNING, queue it (a FAILED
 * one is queued again). *state gets the state before the call. 0 or < 0. */
int awdb_submit(awdb *db, const awdb_key *key, awdb_state *state, core_err *err);
/* The finished field nearest to key for a warm start (same ship, aircraft,
 * rotor mode and domain (deck zone or whole), direction within
 * AWDB_WARM_MAX_DIR_RAD, the wind entering and leaving by the same faces of
 * the CFD grid; distance in WOD velocity). The key's own grid level is
 * preferred; without a field there, the finest coarser level's
 * (coarse-to-fine, by core_grid_rank). 0 with path, 1 if none. A
 * whole-domain ship-only key starts only from its own wind's field on a
 * coarser grid (the same key but for the grid), else from the inflow:
 * oblique winds keep the state they start in, so another wind's field
 * would make the field depend on what the database held. */
#define AWDB_WARM_MAX_DIR_RAD (30.5 * CORE_DEG_TO_RAD)
int awdb_nearest(awdb *db, const awdb_key *key, char *path, size_t n);
/* Each field entry's key as its checksum file holds it, not verified (a
 * client awdb_query()s a key it wants before reading its field): fn(user,
 * key), in no set order, until fn returns non-zero. The number of entries
 * given, or < 0 with err when the fields folder cannot be read; an entry
 * whose checksum file cannot be read is left out. (The flight loop finds
 * its WOD's coupled fields with it.) */
typedef int (*awdb_list_fn)(void *user, const awdb_key *key);
int awdb_list(awdb *db, awdb_list_fn fn, void *user, core_err *err);
/* Mark key as waited for by this process (waiting/NAME.PID, empty): the
 * builder builds requests someone waits for before the others. A flight
 * marks the fields it flies in wait of, a client of awdb_fields the one it
 * waits on. The mark holds while the process runs: awdb_wait_unmark, or
 * the process's end (a builder removes the marks of processes gone; a pid
 * is alive for kill(pid, 0), so the database's clients and builder must
 * share a machine, as builder.lock's flock does). 0, or < 0 with err. */
int awdb_wait_mark(awdb *db, const awdb_key *key, core_err *err);
void awdb_wait_unmark(awdb *db, const awdb_key *key);
/* 1 if a builder holds the database's lock now, 0 if none does. */
int awdb_builder_alive(awdb *db);
/* Number of requests queued and running. */
int awdb_pending(awdb *db, int *queued, int *running);

/* ------------------------------------------------------------- progress */
/* What a database is doing, for a client that waits on it (disim shol's
 * status line). The builder publishes each build's progress in
 * running/NAME.prog ([progress] iteration, max_iterations, residual,
 * fraction, elapsed_s, left_s; written to a temporary name and renamed, at
 * most about once a second, the first at the build's start, removed when
 * the build ends). Advisory: a progress file is not synced to disk, and one
 * that cannot be parsed reads as none. */
typedef struct awdb_run_progress {
    char name[AWDB_NAME_MAX]; /* the key's file stem (awdb_key_name) */
    int have;                 /* 1: the builder published its progress; 0: claimed, not started */
    int iteration;            /* the solver's iteration now */
    int max_iterations;       /* its iteration cap (0: not known) */
    double residual;          /* normalised residual of the last iteration */
    double frac;              /* fraction done: iteration / max_iterations (an upper bound on the
                                 time used: a field can stop at convergence) */
    double elapsed_s;         /* since the build started */
    double left_s;            /* time left at the rate so far up to the cap; < 0: not known yet */
} awdb_run_progress;

#define AWDB_PROGRESS_MAX_RUNS 16
typedef struct awdb_progress {
    int ready;         /* finished fields (entries with their checksum file; not verified here) */
    int queued;        /* requests waiting in queue/ */
    int running;       /* requests claimed by a builder (running/) */
    int builder_alive; /* 1 if a builder holds the database's lock */
    int n_runs;        /* entries of runs[]: the first AWDB_PROGRESS_MAX_RUNS running, by name */
    awdb_run_progress runs[AWDB_PROGRESS_MAX_RUNS];
} awdb_progress;

/* Read the database's state into *out (a directory scan and one small
 * file per running request: cheap enough once a second). Not a snapshot:
 * the folders are read in the order a request moves (queue/, running/,
 * fields/), so a request that moves on during the read counts twice, never
 * not at all; ready never decreases and queued never grows from one read
 * to the next but by new submissions. 0, or < 0 with err when the database
 * folder cannot be read. */
int awdb_progress_read(awdb *db, awdb_progress *out, core_err *err);
/* The progress entry of the build named name (awdb_key_name), or NULL. */
const awdb_run_progress *awdb_progress_find(const awdb_progress *p, const char *name);

/* CRC-64 (ECMA-182) of a file; 0 or < 0 with err. */
int awdb_file_crc64(const char *path, uint64_t *crc, uint64_t *size, core_err *err);

/* ---------------------------------------------------------------- builder */
/* Progress of one build: fraction done, normalised residual, iteration.
 * Returns non-zero to ask the engine to stop. */
typedef int (*awdb_progress_fn)(void *user, double frac, double residual, int iter);

/* A CFD engine (embedded solver, OpenFOAM): build the field for key into
 * out_path (a temporary name in fields/), warm-starting from warm_path when
 * not NULL. Returns 0 ok, non-zero failed with err set; when progress
 * asked it to stop, it may return non-zero with nothing written (the
 * builder then requeues the request, whatever the engine returned). */
typedef struct awdb_engine {
    const char *name;
    int (*build)(void *user, const awdb_key *key, const char *warm_path, const char *out_path,
                 awdb_progress_fn progress, void *progress_user, core_err *err);
    void *user;
    /* May be NULL. Returns 1 with *src filled (canonical) when the engine
     * makes key's field from src's field without a solve once src is in
     * the database (the embedded engine: the mirror image, for a ship
     * symmetric about its centre line); the builder then holds key back
     * while src is running or queued ahead of it, so the pair costs one
     * solve. 0 otherwise. */
    int (*source)(void *user, const awdb_key *key, awdb_key *src);
} awdb_engine;

/* A change of state of a request, for the LCM status messages. */
typedef void (*awdb_status_fn)(void *user, const awdb_key *key, awdb_state state, double frac,
                               double residual, int iter, const char *path, const char *message);

typedef struct awdb_builder_opts {
    int jobs;               /* builds at once (>= 1) */
    int exit_when_idle;     /* return once the queue is empty and nothing runs */
    double poll_s;          /* queue scan interval */
    awdb_status_fn status;  /* may be NULL */
    void *status_user;
    /* Called between scans from the builder's thread (e.g. to handle LCM
     * requests); may be NULL. */
    void (*idle)(void *user);
    void *idle_user;
    /* Least interval between two writes of a build's progress file
     * (running/NAME.prog); 0: 1 s. */
    double progress_interval_s;
} awdb_builder_opts;

/* Run the builder on db until *stop becomes non-zero (or the queue empties
 * with exit_when_idle). Takes builder.lock (a second builder on the same
 * folder fails, after waiting up to 1 s for a client's awdb_builder_alive
 * probe to let go, with an error naming the first one's pid), recovers from a
 * previous crash, then builds the queued requests in this order, each class
 * in submission order:
 *   1. a field the engine makes from another one without a solve
 *      (engine.source: a mirror image) whose source is ready: it costs
 *      nothing, so it never waits behind a solve;
 *   2. a request a running process waits for (awdb_wait_mark), or the
 *      source of such a mirror image;
 *   3. the rest: requests whose requester has ended or does not wait
 *      (`disim airwake --queue`, a flight that has ended).
 * A request the engine makes from a source that is running, or queued
 * ahead of it in this order, is held back until that source is built; so
 * is a whole-domain ship-only request while its own wind's field on a
 * coarser grid is (it starts from that one: awdb_nearest). */
int awdb_builder_run(awdb *db, const awdb_engine *engine, const awdb_builder_opts *opts,
                     volatile sig_atomic_t *stop, core_err *err);

/* ------------------------------------------------------ embedded engine */
/* The embedded RANS solver (cfd) as a builder engine. Ships are looked up
 * by name among the ship files (*.ini) of ships_dir. A whole-domain
 * ship-only field of a ship symmetric about its centre line
 * (core_ship_mirror_symmetric) is the mirror image of the opposite
 * direction's when that one is in the database (cfd_field_mirror_y; its
 * engine.source names it). max_iter 0 keeps the
 * solver's default; each build uses at least `threads` OpenMP threads
 * (cores / jobs) and, from iteration to iteration, its share of the
 * machine's cores among the builds running (a build alone takes them all). */
typedef struct awdb_embedded awdb_embedded;
awdb_embedded *awdb_embedded_create(const char *ships_dir, int max_iter, int threads,
                                    const core_log *log, core_err *err);
void awdb_embedded_destroy(awdb_embedded *e);
/* The database a deck-zone build (awdb_key.zone_ref_mps > 0) reads its
 * ship-only boundary field from (the builder's own); without one such
 * builds fail with an error saying so. */
void awdb_embedded_set_db(awdb_embedded *e, awdb *db);
/* A deck zone's boundary (a key with zone_ref_mps > 0): the ship-only field
 * of the key's ship, direction and grid at its reference speed, loaded from
 * db (awdb_key_zone_boundary); NULL with err when db is NULL or the field
 * is not ready there. Every engine that builds deck zones reads it so. */
struct cfd_field;
struct cfd_field *awdb_zone_boundary(awdb *db, const awdb_key *k, core_err *err);
void awdb_embedded_engine(awdb_embedded *e, awdb_engine *eng);

/* ------------------------------------------------ a client's fields */
/* What a program that reads fields (the coupling, later the flight loop)
 * keeps of the database: the fields it loaded (least recently used
 * dropped first) and a fetch that queues a missing key and waits for the
 * builder, starting one through the caller's launcher when none serves the
 * database. Needs the CFD module. A fetched field stays loaded until
 * cache_n other fields have been fetched after it. */
struct cfd_field;
struct cfd_field_scaled;
struct cfd_airwake_spec;
typedef struct awdb_fields awdb_fields;
typedef struct awdb_fields_opts {
    int cache_n;              /* fields kept loaded, 1 to 32 (default 8) */
    double wait_timeout_s;    /* longest wait for one field (default 3 h) */
    double poll_s;            /* database poll while waiting (default 0.2 s) */
    /* Start a builder on db_dir (e.g. `disim airwaked DB --exit-when-idle`
     * in the background); called while no builder serves the database and
     * a field is wanted. Returns 0 (started, or one of ours is still
     * starting), < 0 it cannot. NULL: never start one (a missing field
     * with no builder is an error). */
    int (*launch)(void *user, const char *db_dir);
    void *launch_user;
    /* Called every poll while a field is waited for (NULL: never), with the
     * key waited for and the seconds waited so far (progress displays). */
    void (*wait_fn)(void *user, const awdb_key *key, double waited_s);
    void *wait_user;
    /* Called when a field file is loaded into the cache (NULL: never). */
    void (*loaded_fn)(void *user, const char *path, const struct cfd_field *f);
    void *loaded_user;
} awdb_fields_opts;

void awdb_fields_opts_default(awdb_fields_opts *o);
/* Over an open database that outlives it. NULL with err. */
awdb_fields *awdb_fields_create(awdb *db, const awdb_fields_opts *o, const core_log *log, core_err *err);
void awdb_fields_destroy(awdb_fields *fc);
/* The field of key (canonicalised in place): loaded from the database when
 * READY, else queued and waited for. NULL with err: the key is invalid,
 * its build failed, no builder serves it (and none can be started), or it
 * was not built within wait_timeout_s. */
const struct cfd_field *awdb_fields_get(awdb_fields *fc, awdb_key *key, core_err *err);
/* A field file by path, through the cache. NULL with err. */
const struct cfd_field *awdb_fields_load(awdb_fields *fc, const char *path, core_err *err);
/* The path of a loaded field; NULL if it is not in the cache. */
const char *awdb_fields_path(const awdb_fields *fc, const struct cfd_field *f);
/* Start a builder (launch) if none serves the database: 0, or < 0. */
int awdb_fields_start_builder(awdb_fields *fc);

/* The WOD speed the ship-only fields are built at (m/s); they serve every
 * speed scaled by v / AWDB_SHIP_ONLY_REF_MPS (the coupling's one-way trims,
 * the flight loop). */
#define AWDB_SHIP_ONLY_REF_MPS 15.0
/* The key of a whole-domain ship-only field (aircraft may be NULL or ""). */
void awdb_key_ship_only(awdb_key *k, const char *ship, const char *aircraft, double speed_mps, double dir_rad,
                        core_grid_level grid);
/* The one-way air at a WOD: the direction's ship-only field, built at
 * ref_speed_mps, scaled to speed_mps (a ship-only airwake scales with the
 * wind speed). 0 with air filled, or -1 with err when the field cannot be
 * had. The field stays loaded until the cache drops it. */
int awdb_fields_ship_only_air(awdb_fields *fc, const char *ship, const char *aircraft, core_grid_level grid,
                              double ref_speed_mps, double speed_mps, double dir_rad,
                              struct cfd_field_scaled *air, core_err *err);

/* The CFD case of a key, the one place a key becomes a solver spec (the
 * builder's engine and `disim airwake` both take it from here, so that a
 * field is the same whoever solved it): ship, WOD, grid level, rotor disk,
 * the monitor line, the isolated rotor's open ship cells, and a deck zone's
 * flag and (rotor off) box; a zone's boundary field, the iteration limit
 * and the grid-study options are the caller's. 0, or < 0 with err. */
int awdb_key_spec(const awdb_key *key, const core_ship *ship, struct cfd_airwake_spec *spec, core_err *err);

/* The CFD actuator disk of a key with the rotor on: centred at the station,
 * tilted by the shaft angles (heading along the ship's), psi = 0 aft;
 * uniform (seed paper eq. 5) or loaded with the key's table and swirl.
 * Returns < 0 for a key with the rotor off. */
struct cfd_disk;
int awdb_key_disk(const awdb_key *key, struct cfd_disk *disk);
/* The height (z in S, m; negative above the deck) of the solver's monitor
 * line for a key: 5 m above the deck for a ship-only field, the hub's
 * height with the rotor on. It also bounds the grid's focus box, so every
 * program that solves a key (the builder, `disim airwake`) must take it
 * from here for the field to be the same. */
double awdb_key_monitor_z_m(const awdb_key *key);

#ifdef __cplusplus
}
#endif
#endif
