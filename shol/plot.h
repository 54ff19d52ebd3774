/* plot.h -- private to shol/: what the envelope plots (plot.c) and the
 * flown envelope's plot (plot_flown.c) share. */
#ifndef DISIM_SHOL_PLOT_H
#define DISIM_SHOL_PLOT_H

#include <cairo.h>

#define SHOL_PLOT_FONT "DejaVu Sans"

/* size, or less so that s fits in width (normal weight). */
double shol_plot_fit_size(cairo_t *cr, const char *s, double size, double width);

#endif
