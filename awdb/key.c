/* key.c -- canonical airwake keys and their file names. Two requests for the
 * same condition must map to one file, so values are rounded to what matters
 * physically (0.01 m/s, 0.01 deg, 1 N, 1 cm) before naming and hashing. */
#include "awdb_private.h"
#ifdef AWDB_HAVE_CFD
#include "cfd.h"
/* the solver version is part of a field's name: a field computed by
 * another version of the solver (other grids, other numerics) is never
 * taken for this one's */
#define AWDB_ENGINE_TAG CFD_VERSION
#else
#define AWDB_ENGINE_TAG "no-engine"
#endif

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

static double round_to(double v, double q) { return q * nearbyint(v / q); }
/* v (in [lo, hi]) rounded to a multiple of q inside [lo, hi] (lo and hi
 * multiples of q): a value near a limit must not round past it, or the
 * canonical key would be refused when read back (its request file, a
 * second canon) */
static double round_in(double v, double q, double lo, double hi)
{
    return round_to(v < lo ? lo : v > hi ? hi : v, q) + 0.0;
}

/* A name in a file stem: letters, digits, '-', '_', '.', not starting with
 * '.' (the database's listings skip hidden files and temporaries: a ship
 * ".x" would have fields built that no listing or nearest search sees). */
static int name_ok(const char *s, int allow_empty)
{
    size_t n = strlen(s);
    if (n == 0)
        return allow_empty;
    if (s[0] == '.')
        return 0;
    for (size_t i = 0; i < n; i++)
        if (!isalnum((unsigned char)s[i]) && s[i] != '-' && s[i] != '_' && s[i] != '.')
            return 0;
    return 1;
}

int awdb_key_canon(awdb_key *k, core_err *err)
{
    if (!name_ok(k->ship, 0))
        return core_err_set(err, -1, "airwake key: ship '%s': expected letters, digits, '-', '_' or '.', not starting with '.'", k->ship);
    if (!name_ok(k->aircraft, 1))
        return core_err_set(err, -1, "airwake key: aircraft '%s': expected letters, digits, '-', '_' or '.', not starting with '.'", k->aircraft);
    if (!isfinite(k->wod_speed_mps) || k->wod_speed_mps < 0.0 || k->wod_speed_mps > 100.0)
        return core_err_set(err, -1, "airwake key: wod_speed_mps = %g: expected 0 to 100", k->wod_speed_mps);
    if (!isfinite(k->wod_dir_rad))
        return core_err_set(err, -1, "airwake key: wod_dir_rad: expected a finite angle");
    if ((int)k->rotor < CORE_ROTOR_OFF || (int)k->rotor > CORE_ROTOR_LOADED)
        return core_err_set(err, -1, "airwake key: rotor = %d: expected 0 (off), 1 (uniform) or 2 (loaded)", k->rotor);
    if (core_grid_rank((int)k->grid) < 0)
        return core_err_set(err, -1, "airwake key: grid = %d: expected 0 (coarse), 1 (default), 2 (fine) or 3 (quick)",
                            k->grid);
    /* the request file's reader takes 0 to 1e7 N: a key it would refuse
     * must be refused here, not queued and failed by the builder */
    if (k->rotor != CORE_ROTOR_OFF && !(isfinite(k->thrust_N) && k->thrust_N > 0.0 && k->thrust_N <= 1e7))
        return core_err_set(err, -1, "airwake key: thrust_N = %g: expected a positive thrust (at most 1e7 N) with the rotor on",
                            k->thrust_N);
    if (!isfinite(k->zone_ref_mps) || k->zone_ref_mps < 0.0 || k->zone_ref_mps > 100.0)
        return core_err_set(err, -1, "airwake key: zone_ref_mps = %g: expected 0 (whole domain) to 100 m/s",
                            k->zone_ref_mps);
    if (k->wod_speed_mps == 0.0) /* a zone needs a ship-only field at a wind */
        k->zone_ref_mps = 0.0;
    const int zone = k->zone_ref_mps > 0.0;
    if ((k->rotor != CORE_ROTOR_OFF || zone) && !(isfinite(k->radius_m) && k->radius_m > 0.1 && k->radius_m < 50.0))
        return core_err_set(err, -1, "airwake key: radius_m = %g: expected 0.1 to 50 m with the rotor on or a zone",
                            k->radius_m);
    if (!isfinite(k->shaft_pitch_rad) || !isfinite(k->shaft_roll_rad) || fabs(k->shaft_pitch_rad) > 1.0 ||
        fabs(k->shaft_roll_rad) > 1.0)
        return core_err_set(err, -1, "airwake key: shaft_pitch_rad, shaft_roll_rad: expected -1 to 1 rad");
    for (int i = 0; i < 3; i++)
        if (!isfinite(k->station_S_m[i]) || fabs(k->station_S_m[i]) > 1000.0)
            return core_err_set(err, -1, "airwake key: station_S_m[%d] = %g: expected -1000 to 1000 m", i, k->station_S_m[i]);
    k->wod_speed_mps = round_to(k->wod_speed_mps, 0.01);
    double d = core_wod_wrap_deg(k->wod_dir_rad * CORE_RAD_TO_DEG);
    d = core_wod_wrap_deg(round_to(d, 0.01));
    k->wod_dir_rad = d * CORE_DEG_TO_RAD;
    /* In calm air the direction means nothing (the aircraft's heading is the
     * ship's): one field serves every direction's hover (the CG-47 sweep
     * built the same calm field for green 60 and green 90). */
    if (k->wod_speed_mps == 0.0)
        k->wod_dir_rad = 0.0;
    k->zone_ref_mps = round_to(k->zone_ref_mps, 0.01);
    if (k->rotor == CORE_ROTOR_OFF && !zone) {
        /* A ship-only field does not depend on the helicopter. */
        k->thrust_N = 0.0;
        k->aircraft[0] = '\0';
        k->station_S_m[0] = k->station_S_m[1] = k->station_S_m[2] = 0.0;
        k->radius_m = k->shaft_pitch_rad = k->shaft_roll_rad = 0.0;
    } else if (k->rotor == CORE_ROTOR_OFF) {
        /* A ship-only field in a deck zone: the zone's box is the rotor's
         * reach from the station, so station and radius name it. */
        k->thrust_N = k->shaft_pitch_rad = k->shaft_roll_rad = 0.0;
        k->radius_m = round_in(k->radius_m, 0.01, 0.11, 49.99); /* inside (0.1, 50) */
        for (int i = 0; i < 3; i++)
            k->station_S_m[i] = round_to(k->station_S_m[i], 0.01) + 0.0;
    } else {
        k->thrust_N = round_in(k->thrust_N, 1.0, 1.0, 1e7); /* a positive thrust stays positive */
        k->radius_m = round_in(k->radius_m, 0.01, 0.11, 49.99);
        /* 0.1 deg steps within 1 rad (57.2958 deg): at most 57.2 deg */
        k->shaft_pitch_rad = round_in(k->shaft_pitch_rad * CORE_RAD_TO_DEG, 0.1, -57.2, 57.2) * CORE_DEG_TO_RAD + 0.0;
        k->shaft_roll_rad = round_in(k->shaft_roll_rad * CORE_RAD_TO_DEG, 0.1, -57.2, 57.2) * CORE_DEG_TO_RAD + 0.0;
        for (int i = 0; i < 3; i++)
            k->station_S_m[i] = round_to(k->station_S_m[i], 0.01) + 0.0; /* no -0 */
    }
    /* Names are read into AWDB_NAME_MAX bytes and end in the hash that
     * tells keys apart: a longer one would lose its hash to truncation, and
     * two keys would share a file. */
    char name[2 * AWDB_NAME_MAX];
    awdb_key_name(k, name, sizeof name);
    if (strlen(name) >= AWDB_NAME_MAX)
        return core_err_set(err, -1, "airwake key: ship '%s', aircraft '%s': names too long (%zu characters together; "
                            "expected at most %zu)", k->ship, k->aircraft, strlen(k->ship) + strlen(k->aircraft),
                            strlen(k->ship) + strlen(k->aircraft) - (strlen(name) - (AWDB_NAME_MAX - 1)));
    if (k->rotor != CORE_ROTOR_LOADED) {
        memset(k->load, 0, sizeof k->load);
        memset(k->swirl, 0, sizeof k->swirl);
        k->torque_Nm = k->root_cut = 0.0;
        k->ccw_from_above = 0;
        return 0;
    }
    if (!isfinite(k->torque_Nm) || k->torque_Nm < 0.0 || k->torque_Nm > 1e7)
        return core_err_set(err, -1, "airwake key: torque_Nm = %g: expected 0 to 1e7 N m", k->torque_Nm);
    if (!isfinite(k->root_cut) || k->root_cut < 0.0 || k->root_cut > 0.5)
        return core_err_set(err, -1, "airwake key: root_cut = %g: expected 0 to 0.5", k->root_cut);
    double sum = 0.0;
    for (int i = 0; i < AWDB_LOAD_NR * AWDB_LOAD_NPSI; i++) {
        if (!isfinite(k->load[i]) || fabs(k->load[i]) > 10.0)
            return core_err_set(err, -1, "airwake key: load[%d] = %g: expected -10 to 10 (relative to the mean)", i,
                                k->load[i]);
        k->load[i] = round_to(k->load[i], 0.001) + 0.0;
        sum += k->load[i];
    }
    if (!(sum > 0.0))
        return core_err_set(err, -1, "airwake key: load: expected a table with a positive mean");
    for (int i = 0; i < AWDB_LOAD_NR; i++) {
        if (!isfinite(k->swirl[i]) || fabs(k->swirl[i]) > 10.0)
            return core_err_set(err, -1, "airwake key: swirl[%d] = %g: expected -10 to 10", i, k->swirl[i]);
        k->swirl[i] = round_to(k->swirl[i], 0.001) + 0.0;
    }
    k->torque_Nm = round_to(k->torque_Nm, 10.0) + 0.0;
    k->root_cut = round_to(k->root_cut, 0.001) + 0.0;
    k->ccw_from_above = k->ccw_from_above != 0;
    return 0;
}

void awdb_key_zone_boundary(const awdb_key *zone, awdb_key *b)
{
    memset(b, 0, sizeof *b);
    snprintf(b->ship, sizeof b->ship, "%s", zone->ship);
    b->wod_speed_mps = zone->zone_ref_mps;
    b->wod_dir_rad = zone->wod_dir_rad;
    b->rotor = CORE_ROTOR_OFF;
    b->grid = zone->grid;
}

void awdb_key_name(const awdb_key *k, char *buf, size_t n)
{
    char text[512]; /* holds the longest canonical key's values: all of them are hashed */
    double dir_deg = k->wod_dir_rad * CORE_RAD_TO_DEG;
    awdb_fmt(text, sizeof text, "%s|%s|%.2f|%.2f|%d|%.0f|%.2f|%.2f|%.2f|%.2f|%.1f|%.1f|%d|%s", k->ship,
             k->aircraft, k->wod_speed_mps, dir_deg, k->rotor, k->thrust_N, k->station_S_m[0],
             k->station_S_m[1], k->station_S_m[2], k->radius_m, k->shaft_pitch_rad * CORE_RAD_TO_DEG,
             k->shaft_roll_rad * CORE_RAD_TO_DEG, k->grid, AWDB_ENGINE_TAG);
    if (k->zone_ref_mps > 0.0) { /* whole-domain names stay as they were */
        size_t l = strlen(text);
        awdb_fmt(text + l, sizeof text - l, "|zone%.2f", k->zone_ref_mps);
    }
    uint64_t h = 1469598103934665603ULL; /* FNV-1a 64 */
    for (const char *p = text; *p; p++) {
        h ^= (unsigned char)*p;
        h *= 1099511628211ULL;
    }
    if (k->rotor == CORE_ROTOR_LOADED) {
        /* the table as canon rounded it: torque, root cut, sense, swirl, load */
        char v[48];
        int nv = AWDB_LOAD_NR * AWDB_LOAD_NPSI + AWDB_LOAD_NR + 3;
        for (int i = 0; i < nv; i++) {
            double x = i == 0 ? k->torque_Nm : i == 1 ? k->root_cut : i == 2 ? k->ccw_from_above
                     : i < 3 + AWDB_LOAD_NR ? k->swirl[i - 3] : k->load[i - 3 - AWDB_LOAD_NR];
            snprintf(v, sizeof v, "|%.3f", x);
            for (const char *p = v; *p; p++) {
                h ^= (unsigned char)*p;
                h *= 1099511628211ULL;
            }
        }
    }
    awdb_fmt(buf, n, "%s_%s_v%05.2f_d%+07.2f_%s_%s%s_%016llx", k->ship,
             k->aircraft[0] ? k->aircraft : "shiponly", k->wod_speed_mps, dir_deg,
             core_rotor_name(k->rotor), core_grid_name(k->grid), k->zone_ref_mps > 0.0 ? "-zone" : "", (unsigned long long)h);
}
