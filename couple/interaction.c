/* interaction.c -- the interaction velocity as the flight model's air
 * (seed paper section 2.5): the coupled field minus the isolated rotor's
 * (same thrust, disk, wind and grid, no ship), under-relaxed against the
 * previous coupling iteration's, plus (deck zone) the whole domain's
 * ship-only airwake in place of the zone's own. Over the rotor disk it is
 * projected on the inflow modes of the flight model's Pitt-Peters model
 * (uniform and first harmonics, linear in r; Peters and HaQuang 1988,
 * "Dynamic inflow for practical applications", JAHS 33(4)); fuselage, tail
 * rotor and empennage see the pointwise field. Assumptions: see couple.c.
 */
#include "couple_priv.h"
#include "sim.h"

#include <math.h>
#include <string.h>

/* The pointwise interaction velocity (coupled - isolated), under-relaxed
 * against the previous iteration's. */
static int interaction_at(const air_interaction *a, const double pos[3], double out[3])
{
    double c[CFD_NVARS], i[CFD_NVARS], pc[CFD_NVARS], pi[CFD_NVARS];
    int rc = cfd_field_sample(a->coupled, pos, c);
    int ri = cfd_field_sample(a->isolated, pos, i);
    double w = a->prev_coupled ? a->w : 1.0;
    if (a->prev_coupled) {
        cfd_field_sample(a->prev_coupled, pos, pc);
        cfd_field_sample(a->prev_isolated, pos, pi);
    }
    for (int k = 0; k < 3; k++)
        out[k] = w * (c[k] - i[k]) + (a->prev_coupled ? (1.0 - w) * (pc[k] - pi[k]) : 0.0);
    if (a->ship_zone) {
        double sw[CFD_NVARS], sz[CFD_NVARS];
        cfd_field_sample(a->ship_whole, pos, sw);
        cfd_field_sample(a->ship_zone, pos, sz);
        for (int k = 0; k < 3; k++)
            out[k] += a->corr_scale * (sw[k] - sz[k]);
    }
    return (rc > 0 || ri > 0) ? 1 : (rc < 0 ? rc : ri);
}

/* The projected interaction's disk (sim_disk_modes: within 1.1 R of the
 * shaft and 0.3 R of the disk plane, flapping blades stay inside). */
static int in_disk(const air_interaction *a, const double pos[3], double *rr, double *psi)
{
    sim_disk_modes dm;
    dm.q_SH = a->q_SH;
    dm.R = a->R;
    return sim_disk_modes_in(&dm, a->hub, pos, rr, psi);
}

static int fit_point(void *user, const double pos[3], double v[3]) { return interaction_at(user, pos, v); }

/* Project the interaction over the disk on the modes of the flight model's
 * own inflow model (Pitt-Peters: uniform and the two first harmonics,
 * linear in r), by area-weighted least squares on a polar grid over 0.2 R
 * to R (sim_disk_modes_fit). Why: pointwise, the difference of two
 * resolved slipstreams is dominated at the blade tips by the slipstream
 * edge, which sits within a cell or two of the tip and moves by a fraction
 * of a cell between the coupled and the isolated solution. On a flat deck in calm air (hub 0.95 R
 * above the deck) the pointwise difference was 0.5-0.7 m/s downward at
 * r = 0.9-0.95 R and 0.5-1.5 m/s upward inboard; the trim, loaded at the
 * tips, took 5 % more collective in ground effect. The projection keeps
 * the disk-scale interaction (ground effect, the airwake's up- and
 * downwash, its gradients) and drops the tip-cell noise; the fuselage,
 * tail and empennage still see the pointwise field. */
void couple_interaction_fit(air_interaction *a, const hfm_disk *d, double R)
{
    memcpy(a->hub, d->hub_S_m, sizeof a->hub);
    a->q_SH = d->q_SH;
    a->R = R;
    sim_disk_modes dm; /* the fit is sim's, shared with the flight loop */
    sim_disk_modes_fit(&dm, d->hub_S_m, d->q_SH, R, fit_point, a);
    memcpy(a->m, dm.m, sizeof a->m);
    memcpy(a->c, dm.c, sizeof a->c);
    memcpy(a->s, dm.s, sizeof a->s);
}

int couple_interaction_air(void *user, const double pos[3], double t, double vel[3])
{
    (void)t;
    air_interaction *a = user;
    double rr, psi;
    if (in_disk(a, pos, &rr, &psi)) {
        for (int k = 0; k < 3; k++)
            vel[k] = a->wind[k] + a->m[k] + rr * (a->c[k] * cos(psi) + a->s[k] * sin(psi));
        return 0;
    }
    double v[3];
    int rc = interaction_at(a, pos, v);
    for (int k = 0; k < 3; k++)
        vel[k] = a->wind[k] + v[k];
    return rc;
}
