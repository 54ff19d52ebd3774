/*
 * core.h -- disim's common code: logging callback, vectors, quaternions,
 * frame transforms (S, E, B), units, the wind-over-deck convention, an INI
 * reader with schema checking, and the ship geometry file.
 *
 * Conventions (docs/conventions.md):
 *  - SI inside; names carry unit and frame where not obvious (vel_S_mps).
 *  - Frames are right-handed: ship frame S (x bow, y starboard, z down, origin
 *    at the landing spot on the deck), Earth frame E (NED), body frame B
 *    (x forward, y right, z down). Euler angles are 3-2-1 (psi, theta, phi).
 *  - WOD direction is where the wind comes FROM, measured from the bow,
 *    positive to starboard, in (-180, 180] deg; the wind velocity in S is
 *    -V (cos dir, sin dir, 0).
 *  - Functions return int: 0 ok, < 0 fatal, > 0 recoverable. The library
 *    never prints; it reports through a core_log callback.
 */
#ifndef DISIM_CORE_H
#define DISIM_CORE_H

#include <stddef.h>
#include <stdint.h>
#include <stdarg.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ units */
#define CORE_KT_TO_MPS 0.514444
#define CORE_KMH_TO_MPS (1.0 / 3.6)
#define CORE_FT_TO_M 0.3048
#define CORE_IN_TO_M 0.0254
#define CORE_SLUGFT2_TO_KGM2 1.35582
#define CORE_LB_TO_KG 0.453592
#define CORE_LBF_TO_N 4.44822
#define CORE_PI 3.14159265358979323846
#define CORE_DEG_TO_RAD (CORE_PI / 180.0)
#define CORE_RAD_TO_DEG (180.0 / CORE_PI)
/* Standard sea-level air (docs/conventions.md). */
#define CORE_RHO_SL_KGPM3 1.225
#define CORE_NU_SL_M2PS 1.46e-5
#define CORE_G_MPS2 9.80665

/* ---------------------------------------------------------------- logging */
enum { CORE_LOG_ERROR = 0, CORE_LOG_WARN = 1, CORE_LOG_INFO = 2, CORE_LOG_DEBUG = 3 };

/* A log sink: level is one of CORE_LOG_*, msg is one line without '\n'. */
typedef void (*core_log_fn)(void *user, int level, const char *msg);

typedef struct core_log {
    core_log_fn fn; /* NULL: messages are dropped */
    void *user;
    int max_level; /* messages above this level are dropped */
} core_log;

/* Format and send one message; safe with log == NULL or log->fn == NULL. */
void core_log_msg(const core_log *log, int level, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* An error that functions fill on failure: the message ("file:line: ...")
 * for people, the code for callers, who branch on it and never on the
 * message's text. core_err_set stores the code it returns. */
typedef struct core_err {
    char msg[1024];
    int code;
} core_err;
/* Codes a caller tells apart (< 0 fatal, > 0 recoverable). */
enum {
    CORE_ERR_FAIL = -1,   /* fatal: the message says what */
    CORE_ERR_NO_TRIM = 2, /* the trim did not converge: a rejection, not a failure */
};

/* A growing text buffer for reports (plain data; zero-initialise it).
 * core_str_printf appends formatted text, growing the buffer as needed;
 * after a failed allocation it appends nothing more and returns -1 (the
 * text so far stays valid and NUL-terminated, and failed stays 1), so a
 * report is never silently cut. core_str_take hands the text (malloc'd,
 * "" when empty) to the caller, or NULL after a failure, freeing it then;
 * either way the buffer is empty again. */
typedef struct core_str {
    char *s;
    size_t len, cap;
    int failed;
} core_str;
int core_str_printf(core_str *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
char *core_str_take(core_str *b);

/* printf into err (if err != NULL); returns code, so `return core_err_set(...)`. */
int core_err_set(core_err *err, int code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Seconds of CLOCK_MONOTONIC: for measuring how long work takes. */
double core_monotonic_s(void);

/* ------------------------------------------------------- vectors, matrices */
typedef struct core_vec3 {
    double x, y, z;
} core_vec3;

/* Unit quaternion (w, x, y, z); q_AB rotates vectors from frame B to frame A:
 * v_A = q_AB * v_B * conj(q_AB). */
typedef struct core_quat {
    double w, x, y, z;
} core_quat;

/* Euler angles 3-2-1 (yaw psi, pitch theta, roll phi), radians. */
typedef struct core_euler {
    double phi_rad, theta_rad, psi_rad;
} core_euler;

/* 3x3 matrix, row major: m[r][c]. */
typedef struct core_mat3 {
    double m[3][3];
} core_mat3;

core_vec3 core_vec3_make(double x, double y, double z);
core_vec3 core_vec3_add(core_vec3 a, core_vec3 b);
core_vec3 core_vec3_sub(core_vec3 a, core_vec3 b);
core_vec3 core_vec3_scale(core_vec3 a, double s);
double core_vec3_dot(core_vec3 a, core_vec3 b);
core_vec3 core_vec3_cross(core_vec3 a, core_vec3 b);
double core_vec3_norm(core_vec3 a);
/* An angle (rad) wrapped into [-pi, pi] as atan2(sin a, cos a): the one
 * wrap of headings and attitude errors (WOD directions: core_wod_wrap_deg). */
double core_wrap_pi(double a_rad);

core_quat core_quat_identity(void);
core_quat core_quat_mul(core_quat a, core_quat b);
core_quat core_quat_conj(core_quat q);
core_quat core_quat_normalize(core_quat q);
/* Rotate v by q: returns q v q*. */
core_vec3 core_quat_rotate(core_quat q, core_vec3 v);
/* Inverse rotation: returns q* v q. */
core_vec3 core_quat_rotate_inv(core_quat q, core_vec3 v);
/* q_AB from 3-2-1 Euler angles of frame B relative to frame A (e.g. A = E,
 * B = body: the aircraft attitude). */
core_quat core_quat_from_euler(core_euler e);
/* Inverse of core_quat_from_euler; theta in [-pi/2, pi/2], phi, psi in (-pi, pi]. */
core_euler core_quat_to_euler(core_quat q);
/* Quaternion time derivative for body rates w_B (rad/s) of frame B in A:
 * qdot = 0.5 q (0, w_B). */
core_quat core_quat_deriv(core_quat q, core_vec3 w_B_radps);

/* Direction cosine matrix C_AB (v_A = C_AB v_B) from Euler angles. */
core_mat3 core_mat3_from_euler(core_euler e);
/* Inverse of core_mat3_from_euler (C_AB to the 3-2-1 angles of B in A);
 * theta in [-pi/2, pi/2], phi, psi in (-pi, pi]. */
core_euler core_mat3_to_euler(core_mat3 m);
core_vec3 core_mat3_mul_vec(core_mat3 m, core_vec3 v);
core_vec3 core_mat3_tmul_vec(core_mat3 m, core_vec3 v); /* m^T v */

/* ---------------------------------------------------------- frame poses */
/* Pose of a moving frame F in E: origin position and attitude q_EF. */
typedef struct core_pose {
    core_vec3 pos_E_m;
    core_quat q_EF;
} core_pose;

/* Point in frame F -> point in E, and back. */
core_vec3 core_pose_point_to_E(const core_pose *f, core_vec3 p_F_m);
core_vec3 core_pose_point_from_E(const core_pose *f, core_vec3 p_E_m);
/* Free vector (no translation) F -> E and back. */
core_vec3 core_pose_vec_to_E(const core_pose *f, core_vec3 v_F);
core_vec3 core_pose_vec_from_E(const core_pose *f, core_vec3 v_E);

/* ------------------------------------------------------- wind over deck */
/* Wrap an angle in degrees into (-180, 180]. */
double core_wod_wrap_deg(double dir_deg);
/* The port-starboard mirror of a WOD direction: green D for red D, wrapped
 * into (-180, 180]; head (0) and stern (180) winds are their own mirror
 * (0 stays +0). */
double core_wod_mirror_deg(double dir_deg);
/* Wind velocity in S for a WOD of speed V (m/s) from dir (rad, from the bow,
 * + to starboard): -V (cos dir, sin dir, 0). */
core_vec3 core_wod_vel_S_mps(double speed_mps, double dir_rad);
/* How a wind crosses an airwake grid aligned with S: for x and y, sign[d] =
 * +1 when the wind blows toward +d (it enters by the min face and leaves by
 * the max face), -1 toward -d, 0 when its component along d is under 5 %
 * of its speed (both faces symmetry planes). Returns 1 in calm air (speed
 * not > 0: no wind, signs 0), else 0. The CFD's boundary types and the
 * airwake database's choice of warm starts both follow this rule. */
int core_wod_faces(double speed_mps, double dir_rad, int sign[2]);
/* Name of a WOD direction as seamen say it: "green 30", "red 90", "head", "stern". */
void core_wod_name(double dir_deg, char *buf, size_t n);
/* A WOD as a flight deck says it, for titles: "25 kt ahead" (within 0.5
 * deg of the bow), "20 kt red 30", "15 kt green 90" (speed and angle
 * rounded to whole numbers). */
void core_wod_label(double speed_mps, double dir_deg, char *buf, size_t n);

/* ---------------------------------------------------------------- folders */
/* Create dir and its missing parents (mkdir -p); 0, or < 0 with err naming
 * the part that could not be made or a path that is not a folder. */
int core_mkdir_p(const char *dir, core_err *err);
/* Before any work that ends in writing to dir: 0 if dir is a folder that
 * can be written in, or does not exist and its nearest existing parent is
 * one; < 0 with err naming the part that is not a folder or cannot be
 * written. Nothing is created. */
int core_dir_check(const char *dir, core_err *err);
/* fsync a file or a folder by path (a folder: the renames in it): 0, or -1
 * with errno set. */
int core_sync_path(const char *path);

/* --------------------------------------------------------------- escaping */
/* in (NULL: "") into out (n bytes, always NUL-terminated) with every byte
 * a terminal would act on or that is not ASCII as \xNN, cut at a whole
 * escape: text from a file or the network made safe to print, log or send
 * on. Idempotent (a backslash is kept). Returns the length written.
 * core_err_set and core_log_msg apply it to every message. */
size_t core_escape(const char *in, char *out, size_t n);
/* CRC-64/XZ of n bytes carried on from crc (0 to start; the result of
 * the bytes before to go on): core_crc64(core_crc64(0, a, na), b, nb) is
 * the checksum of a then b. */
uint64_t core_crc64(uint64_t crc, const void *data, size_t n);
/* The CRC-64/XZ of the stream f's bytes from where it stands to its end
 * (*crc), and their count (*bytes): 0, or -1 on a read error (ferror). */
int core_crc64_file(FILE *f, uint64_t *crc, uint64_t *bytes);

/* ------------------------------------------------------------ input files */
struct stat;
/* 0 if path is a regular file of at most max_bytes (max_bytes < 0: any
 * size); < 0 with err naming the path and what it is otherwise (missing, a
 * folder, a FIFO, a device, a socket, too large). Nothing is opened, so a
 * FIFO does not block. */
int core_file_regular(const char *path, long long max_bytes, core_err *err);
/* The same check on what fstat or stat gave for path (an opened file). */
int core_file_check_stat(const char *path, const struct stat *st, long long max_bytes, core_err *err);
/* The whole of the regular file path, of at most max_bytes (the size read,
 * not the size stat gives: a file that grows meanwhile is refused past
 * it), into a new buffer with a NUL added, its size in *len (a NUL inside
 * is the caller's to refuse); NULL with err (not a regular file, too
 * large, a read error, out of memory). The caller frees it. */
char *core_file_read(const char *path, long long max_bytes, size_t *len, core_err *err);
/* An output's target: 0 if it does not exist or is a regular file (or a
 * link to one); < 0 with err saying what it is otherwise (a folder, a
 * device such as /dev/full, a FIFO), as the output is written to a
 * temporary and renamed over it. */
int core_output_check(const char *path, core_err *err);
/* 1 if a and b name the same file: the same inode when both exist, else
 * the same folder and last part (an output named twice before it exists). */
int core_path_same(const char *a, const char *b);

/* ------------------------------------------------- airwake case options */
/* The named options of an airwake case, each defined here once (the
 * lowest module that the scenario reader, the CFD solver, the database's
 * keys and the coupling all share). Names: core_*_name gives "?" for a
 * value out of range; core_*_parse gives the value, or -1 for NULL or an
 * unknown name; core_*_choices the names joined by '|' for
 * core_ini_get_enum. */

/* The airwake grid levels (cfd/airwake.c gives each its spacing). The
 * three a scenario or a command chooses (CORE_GRID_NLEVELS of them), and
 * CORE_GRID_QUICK, twice the coarse spacing: the first look a flight gets
 * while its own level is solved (the airwake database's builder, docs/
 * usage.md); not a scenario's choice. Its value comes after the others so
 * that the three keep their numbers (the database's field names hash
 * them); core_grid_rank orders the four by spacing. */
typedef enum { CORE_GRID_COARSE = 0, CORE_GRID_DEFAULT = 1, CORE_GRID_FINE = 2, CORE_GRID_QUICK = 3 } core_grid_level;
#define CORE_GRID_NLEVELS 3
/* "coarse", "default", "fine" or "quick". */
const char *core_grid_name(int level);
/* One of the three choices ("quick" is not one: -1). */
int core_grid_parse(const char *s);
/* One of the four levels, "quick" too; -1 otherwise. */
int core_grid_parse_any(const char *s);
const char *core_grid_choices(void);
/* A level's place from the coarsest: quick 0, coarse 1, default 2, fine 3
 * (-1 for a value out of range). */
int core_grid_rank(int level);

/* The rotor in an airwake case: none (ship-only), the uniform actuator
 * disk of the seed paper's eq. 5, or the disk loaded with a trim's blade
 * loads. */
typedef enum { CORE_ROTOR_OFF = 0, CORE_ROTOR_UNIFORM = 1, CORE_ROTOR_LOADED = 2 } core_rotor_mode;
#define CORE_ROTOR_NMODES 3
/* "off", "uniform" or "loaded". */
const char *core_rotor_name(int mode);
int core_rotor_parse(const char *s);
const char *core_rotor_choices(void);

/* Ship-rotor coupling: two-way (the rotor in the CFD, seed paper section
 * 2.5) or one-way (the ship-only airwake). */
typedef enum { CORE_COUPLING_TWO_WAY = 0, CORE_COUPLING_ONE_WAY = 1 } core_coupling_mode;
#define CORE_COUPLING_NMODES 2
/* "two-way" or "one-way". */
const char *core_coupling_name(int mode);
int core_coupling_parse(const char *s);
const char *core_coupling_choices(void);

/* ----------------------------------------------------------- INI reader */
/* An INI file read whole (libinih), each entry with its line number, and a
 * schema checker that reports the file, line, key and what was expected. */
typedef struct core_ini core_ini;

typedef struct core_ini_entry {
    const char *section;
    const char *key;
    const char *value;
    int line;
    int used; /* set when a schema or getter consumed it */
} core_ini_entry;

/* The largest INI file read, far above any real input (bytes). */
#define CORE_INI_MAX_BYTES (16LL * 1024 * 1024)
/* Read path; NULL with err filled on failure: a missing file, one that is
 * not a regular file or is larger than CORE_INI_MAX_BYTES, a NUL byte, a
 * control character other than tab and CR (CRLF line ends) or a byte that is not
 * UTF-8 (file, line and column named), a syntax error. Numbers are read
 * as decimal only (no 0x14, inf or nan). */
core_ini *core_ini_load(const char *path, core_err *err);
/* The same reader on text already in memory (len bytes, no NUL needed at
 * its end): path names it in every message and its folder is where
 * core_ini_get_path resolves relative paths. core_ini_load reads the file
 * whole and parses it here. */
core_ini *core_ini_parse(const char *text, size_t len, const char *path, core_err *err);
void core_ini_destroy(core_ini *ini);
const char *core_ini_path(const core_ini *ini);
size_t core_ini_count(const core_ini *ini);
const core_ini_entry *core_ini_at(const core_ini *ini, size_t i);
/* Last entry for section/key, or NULL. */
const core_ini_entry *core_ini_find(const core_ini *ini, const char *section, const char *key);
/* 1 if the file has a section of that name. */
int core_ini_has_section(const core_ini *ini, const char *section);

/* Typed getters. Each returns 0 on success, 1 if the key is absent and not
 * required (out untouched), < 0 with err "file:line: [section] key: ..." on
 * a wrong type, an out-of-range value, or a missing required key. */
int core_ini_get_double(core_ini *ini, const char *section, const char *key, int required,
                        double min, double max, double *out, core_err *err);
int core_ini_get_int(core_ini *ini, const char *section, const char *key, int required, long min,
                     long max, long *out, core_err *err);
int core_ini_get_bool(core_ini *ini, const char *section, const char *key, int required, int *out,
                      core_err *err);
/* choices is "a|b|c"; *out gets the index of the match. */
int core_ini_get_enum(core_ini *ini, const char *section, const char *key, int required,
                      const char *choices, int *out, core_err *err);
/* String copied into out (size n). */
int core_ini_get_string(core_ini *ini, const char *section, const char *key, int required,
                        char *out, size_t n, core_err *err);
/* A name that becomes part of a file or folder name (a scenario, a ship,
 * an aircraft): letters, digits, '_', '-' and '.', not starting with '.'
 * (no '/', no "..", no blank). */
int core_ini_get_name(core_ini *ini, const char *section, const char *key, int required, char *out,
                      size_t n, core_err *err);
/* A comma-separated list of up to nmax numbers in [min, max]; *count set. */
int core_ini_get_doubles(core_ini *ini, const char *section, const char *key, int required,
                         double min, double max, double *out, int nmax, int *count,
                         core_err *err);
/* A path relative to the INI file's folder; out gets the resolved path, and
 * the file must exist. */
int core_ini_get_path(core_ini *ini, const char *section, const char *key, int required,
                      char *out, size_t n, core_err *err);
/* Mark every entry of a section consumed: for a section another module reads
 * (e.g. an aircraft file's [rejection] criteria, read by shol). */
void core_ini_skip_section(core_ini *ini, const char *section);
/* After all getters ran: the first entry nothing consumed is an error
 * ("unknown key" or "unknown section"), naming its line. */
int core_ini_check_unused(const core_ini *ini, core_err *err);

/* Parse "a:b:c" (start:stop:step) or a single number into up to nmax values. */
int core_parse_range(const char *s, double *out, int nmax, int *count);
/* Parse "X,Y,Z" (three finite numbers) into v. With end NULL nothing may
 * follow Z; otherwise *end points just past Z. 0, or -1 if malformed. */
int core_parse_vec3(const char *s, double v[3], const char **end);

/* -------------------------------------------------------- ship geometry */
/* A ship as blocks in S (x bow, y starboard, z down, origin at the landing
 * spot on the deck). A block is an axis-aligned box; a taper narrows its
 * beam linearly to zero over the last taper_m toward +x (a bow). */
typedef struct core_ship_block {
    char name[32];
    double x0_m, x1_m; /* aft and forward ends, x0 < x1 */
    double y0_m, y1_m; /* port and starboard sides */
    double z0_m, z1_m; /* top (more negative) and bottom, z0 < z1 */
    double bow_taper_m; /* 0: a plain box */
} core_ship_block;

#define CORE_SHIP_MAX_BLOCKS 32

typedef struct core_ship {
    char name[64];
    double length_m, beam_m, draft_m;
    double deck_height_m;   /* flight deck above the waterline */
    double deck_x0_m, deck_x1_m, deck_halfwidth_m; /* flight deck extent in S */
    double anemometer_S_m[3];
    /* Seakeeping (optional keys; sim/ship_motion.c needs them at a sea state
     * above 0): 0 when absent. hull_draft_m is draft_m when absent. */
    double block_coefficient;  /* C_B = displacement volume / (L B T_hull) */
    double hull_draft_m;       /* the hull's draft for the motions (no sonar dome) */
    double roll_period_s;      /* natural roll period */
    double roll_damping_ratio; /* roll damping, fraction of critical */
    int nblocks;
    core_ship_block blocks[CORE_SHIP_MAX_BLOCKS];
} core_ship;

/* Load a ship file (INI, [ship] and one [block NAME] per block; the format
 * is docs/ship-format.md). An unknown section, an anemometer below the
 * waterline, and seakeeping keys given in part (block_coefficient,
 * roll_period_s, roll_damping_ratio: all three or none), are errors. */
int core_ship_load(const char *path, core_ship *ship, core_err *err);
/* The same, with the consistency warnings (CORE_LOG_WARN) on log: a landing
 * spot not on a deck at deck_height_m, an anemometer below the deck, blocks
 * longer or wider than the ship, a flight deck off the blocks. */
int core_ship_load_log(const char *path, core_ship *ship, const core_log *log, core_err *err);
/* The same on a ship file already read (core_ini_load or core_ini_parse;
 * the caller destroys it). */
int core_ship_from_ini(core_ini *ini, core_ship *ship, const core_log *log, core_err *err);
/* Every ship file (*.ini) of a folder, loaded into *ships (malloc'ed, *n
 * of them; the caller frees): 0, or < 0 with err naming the folder or the
 * file (a folder that cannot be read, a path too long, a bad file, none at
 * all), *ships NULL. A ship left out would fail every later request for it
 * with a misleading "no ship of that name": one bad file refuses them all. */
int core_ship_load_dir(const char *dir, core_ship **ships, int *n, core_err *err);
/* The ship of ships[0 .. n-1] named by the first len characters of name
 * (a database key's ship, "SFS2" of "SFS2.isolated"), or NULL. */
const core_ship *core_ship_find(const core_ship *ships, int n, const char *name, size_t len);
/* 1 if point p (S) lies inside one of the ship's blocks. The sea surface is
 * a boundary of the CFD domain, not a block, so it does not count here. */
int core_ship_contains(const core_ship *ship, core_vec3 p_S_m);
/* 1 if the ship's blocks map onto themselves under the port-starboard
 * mirror y -> -y (each block onto itself or onto another block, ends and
 * heights equal within tol_m; tapers included), else 0. The SFS2, CG-47
 * and LPD-17 of scenarios/ships are (their superstructures are modelled on
 * the centre line).
 * For such a ship the airwake of a wind from green D is the mirror image
 * of red D's (cfd_field_mirror_y). */
int core_ship_mirror_symmetric(const core_ship *ship, double tol_m);

#ifdef __cplusplus
}
#endif
#endif
