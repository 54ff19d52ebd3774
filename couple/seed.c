/* seed.c -- the store of each direction's last coupled interaction, the
 * start (iteration 0) of the next speed's coupled point in that direction
 * (couple_settings.seed_from_previous). One per direction: the envelope
 * sweeps every direction before it walks any down, and a walk-down's first
 * point is seeded from its own direction's last point, as in a run of that
 * direction alone (the same trims, hence the same database keys). */
#include "couple_priv.h"

#include <math.h>
#include <stdio.h>

/* The seed of a direction, or NULL. */
struct couple_seed_slot *couple_seed_find(couple_ctx *c, double dir)
{
    for (int i = 0; i < SEED_DIRS; i++)
        if (c->seeds[i].valid && fabs(c->seeds[i].dir - dir) < 1e-9)
            return &c->seeds[i];
    return NULL;
}

/* The slot for a direction's seed: its own, a free one or the least
 * recently stored. */
struct couple_seed_slot *couple_seed_slot(couple_ctx *c, double dir)
{
    struct couple_seed_slot *s = couple_seed_find(c, dir);
    if (s)
        return s;
    int lru = 0;
    for (int i = 0; i < SEED_DIRS; i++) {
        if (!c->seeds[i].valid)
            return &c->seeds[i];
        if (c->seeds[i].used < c->seeds[lru].used)
            lru = i;
    }
    return &c->seeds[lru];
}

void couple_seed_keep(couple_ctx *c, double v, double dir, const air_interaction *ai)
{
    const char *pc = awdb_fields_path(c->fc, ai->coupled), *pi = awdb_fields_path(c->fc, ai->isolated);
    const char *ppc = ai->prev_coupled ? awdb_fields_path(c->fc, ai->prev_coupled) : "";
    const char *ppi = ai->prev_isolated ? awdb_fields_path(c->fc, ai->prev_isolated) : "";
    struct couple_seed_slot *ss = couple_seed_slot(c, dir);
    ss->valid = pc && pi && ppc && ppi;
    if (!ss->valid)
        return;
    ss->v = v;
    ss->dir = dir;
    ss->used = ++c->seed_tick;
    snprintf(ss->coupled, sizeof ss->coupled, "%s", pc);
    snprintf(ss->isolated, sizeof ss->isolated, "%s", pi);
    snprintf(ss->prev_coupled, sizeof ss->prev_coupled, "%s", ppc);
    snprintf(ss->prev_isolated, sizeof ss->prev_isolated, "%s", ppi);
    ss->ai = *ai;
    ss->ai.coupled = ss->ai.isolated = ss->ai.prev_coupled = ss->ai.prev_isolated = NULL;
}
