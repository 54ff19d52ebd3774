/* shol_bands.h -- disim shol's uncertainty bands (issue 28): the measured
 * spreads behind each direction's band gathered from the run and the
 * database, then shol_band_compute (shol/band.c, docs/shol.md
 * "Uncertainty bands"). */
#ifndef DISIM_APP_SHOL_BANDS_H
#define DISIM_APP_SHOL_BANDS_H

#include "awdb.h"
#include "couple.h"
#include "hfm.h"
#include "shol.h"

/* --band-grid and --band-grid-csv. */
#define APP_BAND_GRID_AUTO (-1) /* another level whose fields the database has for some directions */
#define APP_BAND_GRID_NONE (-2)
typedef struct app_band_opts {
    int grid;             /* APP_BAND_GRID_AUTO, _NONE, or a core_grid_level (its fields built if missing) */
    const char *grid_csv; /* the second grid's envelope from an earlier run's shol.csv; NULL: none */
} app_band_opts;

/* Parse --band-grid's value: auto, none, coarse, default or fine; < 0 if
 * none of those. */
int app_band_grid_parse(const char *s);

/* The bands of r1, the one-way envelope on cs->grid that the context one
 * trimmed: the window spreads of one's fields (each direction's ship-only
 * field: 0 converged, max(mean_drift, mean_change) averaged, unknown
 * otherwise), the second grid's one-way envelope (o->grid_csv, or a
 * second one-way sweep on the level o->grid names, auto: the directions
 * whose ship-only field the database already has at the first level of
 * finer-then-coarser that has any), and the sensitivity. With r2 (the
 * two-way envelope over r1), r2's bands too: the same window spreads, and
 * the one-way grid spread (second grid minus r1) applied to r2. One line
 * per direction on stderr. 0, or < 0 with err. */
int app_shol_bands(const app_band_opts *o, const hfm_aircraft *ac, const core_ship *ship, awdb *db,
                   const couple_settings *cs, couple_ctx *one, const shol_settings *set, shol_result *r1,
                   shol_result *r2, const core_log *log, core_err *err);

#endif
