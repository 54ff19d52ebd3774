/* scene.c -- what the view draws: a run's ship, aircraft and seaway
 * (sim_run_scene: the seaway its own, rebuilt as the flight's is) as a
 * render_scene, and the samples behind the frame rate and latency
 * figures. */
#include "otw_priv.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int otw_scene_open(otw_scene *s, const sim_run_info *ri, unsigned overlays, core_err *err)
{
    memset(s, 0, sizeof *s);
    if (sim_run_scene_open(&s->run, ri, NULL, err) != 0)
        return -1;
    snprintf(s->title, sizeof s->title, "%s", s->run.name);
    s->sc.sea = sim_ship_motion_elevation;
    s->sc.overlays = overlays;
    s->sc.air_ref_mps = 1.0;
    otw_scene_moved(s);
    s->open = 1;
    return 0;
}

void otw_scene_moved(otw_scene *s)
{
    s->sc.ship = &s->run.ship;
    s->sc.heli = &s->run.geom;
    s->sc.sea_user = s->run.sea;
    s->sc.title = s->title;
}

void otw_scene_close(otw_scene *s)
{
    sim_run_scene_close(&s->run);
    memset(s, 0, sizeof *s);
}

int otw_samples_add(otw_samples *s, double x)
{
    if (s->n == s->cap) {
        long cap = s->cap ? 2 * s->cap : 4096;
        double *v = realloc(s->v, (size_t)cap * sizeof *v);
        if (!v)
            return -1;
        s->v = v, s->cap = cap;
    }
    s->v[s->n++] = x;
    return 0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

double otw_samples_quantile(const otw_samples *s, long last, double q)
{
    long n = last > 0 && last < s->n ? last : s->n;
    if (n <= 0)
        return NAN;
    double *v = malloc((size_t)n * sizeof *v);
    if (!v)
        return NAN;
    memcpy(v, s->v + (s->n - n), (size_t)n * sizeof *v);
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    /* the nearest rank */
    long k = (long)ceil(q * (double)n) - 1;
    k = k < 0 ? 0 : k >= n ? n - 1 : k;
    double r = v[k];
    free(v);
    return r;
}

void otw_samples_free(otw_samples *s)
{
    free(s->v);
    memset(s, 0, sizeof *s);
}
