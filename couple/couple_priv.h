/* couple_priv.h -- the coupling library's private parts: the context, the
 * interaction-velocity air source (interaction.c), the store of each
 * direction's last coupled interaction (seed.c) and the field records of
 * the report (report.c). */
#ifndef DISIM_COUPLE_PRIV_H
#define DISIM_COUPLE_PRIV_H

#include "cfd.h"
#include "couple.h"

/* fields kept loaded: a coupled iteration holds six at once (coupled,
 * isolated, their previous iteration's, and the zone's two ship-only) */
#define COUPLE_CACHE_N 8
/* seed a coupled point with the interaction of one at most this far in
 * speed (a point trimmed again at the same speed is not seeded: it starts
 * from free air as before and re-reads its fields) */
#define SEED_MAX_DV_MPS 3.0
/* seeds kept: one per direction, a full circle in 5 deg steps */
#define SEED_DIRS 72

/* The interaction velocity, under-relaxed: weight w on this iteration's
 * fields and 1 - w on the previous iteration's (prev_coupled NULL: none). */
typedef struct air_interaction {
    const cfd_field *coupled, *isolated;
    const cfd_field *prev_coupled, *prev_isolated;
    double w;
    double wind[3];
    /* the interaction over the rotor disk, projected on the Pitt-Peters
     * modes (see disk_fit): v_k(r, psi) = m[k] + (r/R)(c[k] cos psi +
     * s[k] sin psi), psi from the hub frame's x axis */
    double hub[3], R;
    core_quat q_SH;
    double m[3], c[3], s[3];
    /* deck zone: corr_scale (ship_whole - ship_zone), the whole domain's
     * ship-only airwake in place of the zone's own (NULL: none) */
    const cfd_field *ship_whole, *ship_zone;
    double corr_scale;
} air_interaction;

struct couple_ctx {
    const hfm_aircraft *ac;
    const core_ship *ship;
    awdb *db;
    couple_settings s;
    const core_log *log;
    hfm_trim *trim;
    hfm_disk *disk;
    awdb_fields *fc;        /* the fields loaded from db */
    /* The warm start of each direction: its last converged trim. Per
     * direction, so that a direction's trims depend on its own earlier
     * trims only, never on the order the directions are swept in: a sweep
     * dealt over several processes (disim shol under mpirun) gives the
     * serial run's numbers bit for bit. */
    struct couple_warm {
        double dir;
        hfm_trim_result r;
    } *warm;
    int nwarm, capwarm;
    couple_point *hist;
    int nhist, caphist;
    char last_error[1024];
    couple_field_info *fields;
    int nfields, capfields;
    /* The interaction of the last coupled point of each direction (the
     * next speed's seed there): its air with the field pointers cleared
     * (the cache may drop the fields) and the fields' database paths (""
     * where ai has none). One per direction: the envelope sweeps every
     * direction before it walks any down, and a walk-down's first point
     * is seeded from its own direction's last point, as in a run of that
     * direction alone (the same trims, hence the same database keys). */
    struct couple_seed_slot {
        int valid;
        double v, dir;
        unsigned long used;
        air_interaction ai;
        char coupled[1024], isolated[1024], prev_coupled[1024], prev_isolated[1024];
    } seeds[SEED_DIRS];
    unsigned long seed_tick;
};

/* interaction.c: fit the interaction over the rotor disk d of radius R
 * (hub, shaft and the Pitt-Peters mode coefficients of a), and the air of
 * an air_interaction (an hfm_air function: the wind plus the interaction,
 * the disk's fitted modes inside the disk). */
void couple_interaction_fit(air_interaction *a, const hfm_disk *d, double R);
int couple_interaction_air(void *user, const double pos[3], double t, double vel[3]);

/* seed.c: the seed of a direction (NULL: none), and the slot for a
 * direction's seed (its own, a free one or the least recently stored). */
struct couple_seed_slot *couple_seed_find(couple_ctx *c, double dir);
struct couple_seed_slot *couple_seed_slot(couple_ctx *c, double dir);
/* Keep a converged point's interaction ai at speed v as its direction's
 * seed (the fields by their database paths, as the cache may drop them). */
void couple_seed_keep(couple_ctx *c, double v, double dir, const air_interaction *ai);

/* report.c: record a loaded field's solver state once (an
 * awdb_fields_opts.loaded_fn; user is the couple_ctx). */
void couple_field_note(void *user, const char *path, const cfd_field *f);

#endif
