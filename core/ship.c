/* ship.c -- ship geometry files: the ship as boxes (with an optional bow
 * taper) in the ship frame S, for the CFD blocking, deck contact and renders.
 *
 * File format (INI):
 *   [ship]   name, length_m, beam_m, draft_m, deck_height_m (flight deck above
 *            the waterline), deck_x_m = aft,fwd and deck_halfwidth_m (flight
 *            deck extent in S), anemometer_S_m = x,y,z
 *   [block NAME]  x_m = aft,fwd (S), y_m = port,starboard (S),
 *            height_m = bottom,top above the waterline, bow_taper_m (optional)
 * Heights above the waterline are what drawings give; S has z down from the
 * deck, so z = deck_height_m - height. */
#include "core.h"

#include <math.h>
#include <stdio.h>
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

int core_ship_load(const char *path, core_ship *ship, core_err *err)
{
    memset(ship, 0, sizeof *ship);
    core_ini *ini = core_ini_load(path, err);
    if (!ini)
        return -1;
    int rc = 0;
    const char *S = "ship";
    double pair[2], anem[3];
    int n = 0;
    if ((rc = core_ini_get_string(ini, S, "name", 1, ship->name, sizeof ship->name, err)) ||
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
out:
    core_ini_destroy(ini);
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
