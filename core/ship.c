/* ship.c -- ship geometry files: the ship as boxes (with an optional bow
 * taper) in the ship frame S, for the CFD blocking, deck contact and renders.
 *
 * File format (INI):
 *   [ship]   name, length_m, beam_m, draft_m, deck_height_m (flight deck above
 *            the waterline), deck_x_m = aft,fwd and deck_halfwidth_m (flight
 *            deck extent in S), anemometer_S_m = x,y,z; the seakeeping keys
 *            block_coefficient, roll_period_s, roll_damping_ratio (all or
 *            none) and hull_draft_m (optional) for the ship's motion
 *   [block NAME]  x_m = aft,fwd (S), y_m = port,starboard (S),
 *            height_m = bottom,top above the waterline, bow_taper_m (optional)
 * Heights above the waterline are what drawings give; S has z down from the
 * deck, so z = deck_height_m - height. The format, key by key, is
 * docs/ship-format.md. Beyond each key's range: an unknown section is named
 * before any key is read, an anemometer below the waterline is refused, and
 * (core_ship_load_log) the slips that keep every value in range are warned
 * about: heights measured from the deck instead of the waterline (the landing
 * spot is then not on a deck at deck_height_m), an anemometer below the deck
 * (z taken up-positive), blocks beyond the ship's length or beam, a flight
 * deck that no block carries. */
#include "core.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int get_pair(core_ini *ini, const char *sec, const char *key, double lo, double hi,
                    double out[2], core_err *err)
{
    int n = 0;
    int rc = core_ini_get_doubles(ini, sec, key, 1, lo, hi, out, 2, &n, err);
    if (rc)
        return rc;
    const core_ini_entry *e = core_ini_find(ini, sec, key);
    if (n != 2)
        return core_err_set(err, -1, "%s:%d: [%s] %s: expected two numbers 'a, b'",
                            core_ini_path(ini), e->line, sec, key);
    if (!(out[0] < out[1]))
        return core_err_set(err, -1, "%s:%d: [%s] %s = %g, %g: expected the first below the second",
                            core_ini_path(ini), e->line, sec, key, out[0], out[1]);
    return 0;
}

/* Every section is [ship] or [block NAME]. */
static int check_sections(const core_ini *ini, core_err *err)
{
    for (size_t i = 0; i < core_ini_count(ini); i++) {
        const core_ini_entry *e = core_ini_at(ini, i);
        if (strcmp(e->section, "ship") != 0 && strncmp(e->section, "block ", 6) != 0)
            return core_err_set(err, -1,
                                "%s:%d: unknown section [%s] (a ship file has [ship] and one [block NAME] "
                                "per block)",
                                core_ini_path(ini), e->line, e->section);
    }
    return 0;
}

static int key_line(const core_ini *ini, const char *sec, const char *key)
{
    const core_ini_entry *e = core_ini_find(ini, sec, key);
    return e ? e->line : 0;
}

/* The consistency warnings of a loaded ship (see the file's opening). */
static void warn_ship(const core_ini *ini, const core_ship *ship, const core_log *log)
{
    const char *path = core_ini_path(ini);
    const double tol = 0.05; /* m */
    double x0 = 1e30, x1 = -1e30, y0 = 1e30, y1 = -1e30, top = -1e30, fwd = -1e30, aft = 1e30;
    for (int i = 0; i < ship->nblocks; i++) {
        const core_ship_block *b = &ship->blocks[i];
        x0 = fmin(x0, b->x0_m);
        x1 = fmax(x1, b->x1_m);
        y0 = fmin(y0, b->y0_m);
        y1 = fmax(y1, b->y1_m);
        /* the top of the blocks that carry the landing spot (S origin), height above the waterline */
        if (b->x0_m <= 0.0 && b->x1_m >= 0.0 && b->y0_m <= 0.0 && b->y1_m >= 0.0)
            top = fmax(top, ship->deck_height_m - b->z0_m);
        /* the extent in x of the blocks whose top is the flight deck */
        if (fabs(b->z0_m) <= tol) { /* z0 is the top (z down from the deck) */
            aft = fmin(aft, b->x0_m);
            fwd = fmax(fwd, b->x1_m);
        }
    }
    if (top < -1e29)
        core_log_msg(log, CORE_LOG_WARN,
                     "%s: no [block] carries the landing spot (x = 0, y = 0 of S): S has its origin at the centre "
                     "of the landing spot on the deck",
                     path);
    else if (fabs(top - ship->deck_height_m) > tol)
        core_log_msg(log, CORE_LOG_WARN,
                     "%s:%d: [ship] deck_height_m = %g: the blocks under the landing spot reach %g m above the "
                     "waterline, so the landing spot is not on a deck at deck_height_m: block height_m values are "
                     "metres above the WATERLINE (not the deck)",
                     path, key_line(ini, "ship", "deck_height_m"), ship->deck_height_m, top);
    else if (ship->deck_x0_m < aft - tol || ship->deck_x1_m > fwd + tol)
        core_log_msg(log, CORE_LOG_WARN,
                     "%s:%d: [ship] deck_x_m = %g, %g: beyond the blocks whose top is the deck (x %g to %g)", path,
                     key_line(ini, "ship", "deck_x_m"), ship->deck_x0_m, ship->deck_x1_m, aft, fwd);
    if (ship->anemometer_S_m[2] > 0.0)
        core_log_msg(log, CORE_LOG_WARN,
                     "%s:%d: [ship] anemometer_S_m: z = %g m is below the flight deck (S has z down: an anemometer "
                     "on a mast above the deck has z < 0)",
                     path, key_line(ini, "ship", "anemometer_S_m"), ship->anemometer_S_m[2]);
    if (x1 - x0 > ship->length_m * 1.02)
        core_log_msg(log, CORE_LOG_WARN,
                     "%s:%d: [ship] length_m = %g: the blocks span %g m (x %g to %g), longer than the ship", path,
                     key_line(ini, "ship", "length_m"), ship->length_m, x1 - x0, x0, x1);
    if (y1 - y0 > ship->beam_m * 1.02)
        core_log_msg(log, CORE_LOG_WARN,
                     "%s:%d: [ship] beam_m = %g: the blocks span %g m (y %g to %g), wider than the ship", path,
                     key_line(ini, "ship", "beam_m"), ship->beam_m, y1 - y0, y0, y1);
    if (ship->deck_halfwidth_m > 0.5 * ship->beam_m * 1.02)
        core_log_msg(log, CORE_LOG_WARN,
                     "%s:%d: [ship] deck_halfwidth_m = %g: wider than half the beam (%g m): the key is the HALF width",
                     path, key_line(ini, "ship", "deck_halfwidth_m"), ship->deck_halfwidth_m, 0.5 * ship->beam_m);
}

/* The seakeeping keys of [ship] (optional; sim/ship_motion.c uses them):
 * the three that the motion needs come together or not at all, so that a
 * forgotten one is named here rather than when a sea state is asked for. */
static int read_seakeeping(core_ini *ini, core_ship *ship, core_err *err)
{
    static const char *const keys[3] = {"block_coefficient", "roll_period_s", "roll_damping_ratio"};
    static const double lo[3] = {0.3, 2.0, 0.005}, hi[3] = {1.0, 60.0, 1.0};
    double *out[3] = {&ship->block_coefficient, &ship->roll_period_s, &ship->roll_damping_ratio};
    int given = -1, missing = -1;
    for (int i = 0; i < 3; i++) {
        int rc = core_ini_get_double(ini, "ship", keys[i], 0, lo[i], hi[i], out[i], err);
        if (rc < 0)
            return rc;
        if (rc == 0 && given < 0)
            given = i;
        if (rc == 1 && missing < 0)
            missing = i;
    }
    if (given >= 0 && missing >= 0)
        return core_err_set(err, -1,
                            "%s:%d: [ship] %s given without %s: the seakeeping keys block_coefficient, "
                            "roll_period_s and roll_damping_ratio come together (docs/ship-format.md)",
                            core_ini_path(ini), key_line(ini, "ship", keys[given]), keys[given], keys[missing]);
    ship->hull_draft_m = ship->draft_m;
    int rc = core_ini_get_double(ini, "ship", "hull_draft_m", 0, 0.1, 50.0, &ship->hull_draft_m, err);
    return rc < 0 ? rc : 0;
}

int core_ship_load(const char *path, core_ship *ship, core_err *err)
{
    return core_ship_load_log(path, ship, NULL, err);
}

int core_ship_load_log(const char *path, core_ship *ship, const core_log *log, core_err *err)
{
    memset(ship, 0, sizeof *ship);
    core_ini *ini = core_ini_load(path, err);
    if (!ini)
        return -1;
    int rc = core_ship_from_ini(ini, ship, log, err);
    core_ini_destroy(ini);
    return rc;
}

int core_ship_from_ini(core_ini *ini, core_ship *ship, const core_log *log, core_err *err)
{
    memset(ship, 0, sizeof *ship);
    const char *path = core_ini_path(ini);
    int rc = 0;
    const char *S = "ship";
    double pair[2], anem[3];
    int n = 0;
    if ((rc = check_sections(ini, err)))
        goto out;
    if ((rc = core_ini_get_name(ini, S, "name", 1, ship->name, sizeof ship->name, err)) ||
        (rc = core_ini_get_double(ini, S, "length_m", 1, 1.0, 500.0, &ship->length_m, err)) ||
        (rc = core_ini_get_double(ini, S, "beam_m", 1, 1.0, 100.0, &ship->beam_m, err)) ||
        (rc = core_ini_get_double(ini, S, "draft_m", 1, 0.0, 50.0, &ship->draft_m, err)) ||
        (rc = core_ini_get_double(ini, S, "deck_height_m", 1, 0.0, 60.0, &ship->deck_height_m, err)) ||
        (rc = get_pair(ini, S, "deck_x_m", -500.0, 500.0, pair, err)) ||
        (rc = core_ini_get_double(ini, S, "deck_halfwidth_m", 1, 0.5, 50.0,
                                  &ship->deck_halfwidth_m, err)) ||
        (rc = core_ini_get_doubles(ini, S, "anemometer_S_m", 1, -500.0, 500.0, anem, 3, &n, err)))
        goto out;
    ship->deck_x0_m = pair[0];
    ship->deck_x1_m = pair[1];
    if (n != 3) {
        rc = core_err_set(err, -1, "%s:%d: [ship] anemometer_S_m: expected three numbers x, y, z",
                          path, core_ini_find(ini, S, "anemometer_S_m")->line);
        goto out;
    }
    memcpy(ship->anemometer_S_m, anem, sizeof anem);
    if (anem[2] > ship->deck_height_m) {
        rc = core_err_set(err, -1,
                          "%s:%d: [ship] anemometer_S_m: z = %g m is %g m below the waterline (S has z down from "
                          "the deck, deck_height_m = %g above the waterline): an anemometer above the deck has z < 0",
                          path, core_ini_find(ini, S, "anemometer_S_m")->line, anem[2],
                          anem[2] - ship->deck_height_m, ship->deck_height_m);
        goto out;
    }

    if ((rc = read_seakeeping(ini, ship, err)))
        goto out;

    for (size_t i = 0; i < core_ini_count(ini); i++) {
        const core_ini_entry *e = core_ini_at(ini, i);
        if (strncmp(e->section, "block ", 6) != 0)
            continue;
        int seen = 0;
        for (int b = 0; b < ship->nblocks; b++)
            if (strcmp(ship->blocks[b].name, e->section + 6) == 0)
                seen = 1;
        if (seen)
            continue;
        /* a name cut to fit blk->name would never match its section again,
         * and each of the section's keys would add the block once more */
        size_t nl = strlen(e->section + 6);
        if (nl == 0 || nl >= sizeof ship->blocks[0].name) {
            rc = core_err_set(err, -1, "%s:%d: [%s]: expected a block name of 1 to %zu characters",
                              path, e->line, e->section, sizeof ship->blocks[0].name - 1);
            goto out;
        }
        if (ship->nblocks == CORE_SHIP_MAX_BLOCKS) {
            rc = core_err_set(err, -1, "%s:%d: [%s]: more than %d blocks", path, e->line,
                              e->section, CORE_SHIP_MAX_BLOCKS);
            goto out;
        }
        core_ship_block *blk = &ship->blocks[ship->nblocks];
        char sec[64];
        snprintf(sec, sizeof sec, "%s", e->section);
        snprintf(blk->name, sizeof blk->name, "%s", e->section + 6);
        double h[2];
        if ((rc = get_pair(ini, sec, "x_m", -500.0, 500.0, pair, err)))
            goto out;
        blk->x0_m = pair[0];
        blk->x1_m = pair[1];
        if ((rc = get_pair(ini, sec, "y_m", -100.0, 100.0, pair, err)))
            goto out;
        blk->y0_m = pair[0];
        blk->y1_m = pair[1];
        if ((rc = get_pair(ini, sec, "height_m", -50.0, 200.0, h, err)))
            goto out;
        blk->z0_m = ship->deck_height_m - h[1];
        blk->z1_m = ship->deck_height_m - h[0];
        blk->bow_taper_m = 0.0;
        rc = core_ini_get_double(ini, sec, "bow_taper_m", 0, 0.0, blk->x1_m - blk->x0_m,
                                 &blk->bow_taper_m, err);
        if (rc < 0)
            goto out;
        rc = 0;
        ship->nblocks++;
    }
    if (ship->nblocks == 0) {
        rc = core_err_set(err, -1, "%s: expected at least one [block NAME] section", path);
        goto out;
    }
    rc = core_ini_check_unused(ini, err);
    if (rc == 0 && log)
        warn_ship(ini, ship, log);
out:
    return rc;
}

int core_ship_contains(const core_ship *ship, core_vec3 p)
{
    for (int i = 0; i < ship->nblocks; i++) {
        const core_ship_block *b = &ship->blocks[i];
        if (p.x < b->x0_m || p.x > b->x1_m || p.z < b->z0_m || p.z > b->z1_m)
            continue;
        double y0 = b->y0_m, y1 = b->y1_m;
        if (b->bow_taper_m > 0.0 && p.x > b->x1_m - b->bow_taper_m) {
            /* The beam narrows linearly to a point on the block's centre line. */
            double f = (b->x1_m - p.x) / b->bow_taper_m;
            double yc = 0.5 * (y0 + y1), hw = 0.5 * (y1 - y0) * f;
            y0 = yc - hw;
            y1 = yc + hw;
        }
        if (p.y >= y0 && p.y <= y1)
            return 1;
    }
    return 0;
}

/* Whether block b, mirrored, is block c. */
static int mirror_match(const core_ship_block *b, const core_ship_block *c, double tol)
{
    return fabs(b->x0_m - c->x0_m) <= tol && fabs(b->x1_m - c->x1_m) <= tol && fabs(b->z0_m - c->z0_m) <= tol &&
           fabs(b->z1_m - c->z1_m) <= tol && fabs(b->y0_m + c->y1_m) <= tol && fabs(b->y1_m + c->y0_m) <= tol &&
           fabs(b->bow_taper_m - c->bow_taper_m) <= tol;
}

int core_ship_mirror_symmetric(const core_ship *ship, double tol_m)
{
    /* every block needs a mirror partner, and no block serves as the
     * partner of two (so duplicate blocks on one side do not pass) */
    unsigned char used[CORE_SHIP_MAX_BLOCKS] = {0};
    for (int i = 0; i < ship->nblocks; i++) {
        int found = -1;
        for (int k = 0; k < ship->nblocks && found < 0; k++)
            if (!used[k] && mirror_match(&ship->blocks[i], &ship->blocks[k], tol_m))
                found = k;
        if (found < 0)
            return 0;
        used[found] = 1;
    }
    return ship->nblocks > 0;
}

const core_ship *core_ship_find(const core_ship *ships, int n, const char *name, size_t len)
{
    for (int i = 0; i < n; i++)
        if (strlen(ships[i].name) == len && !strncmp(ships[i].name, name, len))
            return &ships[i];
    return NULL;
}

int core_ship_load_dir(const char *dir, core_ship **ships, int *n, core_err *err)
{
    *ships = NULL;
    *n = 0;
    DIR *d = opendir(dir);
    if (!d)
        return core_err_set(err, -1, "%s: cannot open the ships folder", dir);
    core_ship *all = NULL;
    int count = 0, rc = 0;
    struct dirent *de;
    while (rc == 0 && (de = readdir(d))) {
        size_t l = strlen(de->d_name);
        if (l < 5 || strcmp(de->d_name + l - 4, ".ini"))
            continue;
        char p[1024];
        core_ship *grown = NULL;
        if (snprintf(p, sizeof p, "%s/%s", dir, de->d_name) >= (int)sizeof p)
            rc = core_err_set(err, -1, "ship file path longer than %zu characters: %s/%s", sizeof p - 1, dir,
                              de->d_name);
        else if (!(grown = realloc(all, (size_t)(count + 1) * sizeof *grown)))
            rc = core_err_set(err, -1, "%s: out of memory loading the ships", p);
        else if ((all = grown), core_ship_load(p, &all[count], err) != 0)
            rc = -1;
        else
            count++;
    }
    closedir(d);
    if (rc == 0 && count == 0)
        rc = core_err_set(err, -1, "%s: no ship files (*.ini)", dir);
    if (rc != 0) {
        free(all);
        return -1;
    }
    *ships = all;
    *n = count;
    return 0;
}
