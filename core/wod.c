/* wod.c -- the wind-over-deck convention (docs/conventions.md): direction the
 * wind comes FROM, measured from the bow, positive to starboard ("green"),
 * negative to port ("red"), in (-180, 180]; velocity in S = -V (cos dir,
 * sin dir, 0). */
#include "core.h"

#include <math.h>
#include <stdio.h>

double core_wod_wrap_deg(double d)
{
    d = fmod(d, 360.0);
    if (d > 180.0)
        d -= 360.0;
    if (d <= -180.0)
        d += 360.0;
    return d;
}

double core_wod_mirror_deg(double d)
{
    /* + 0.0 turns the mirror of a head wind, -0, into +0 */
    return core_wod_wrap_deg(-d) + 0.0;
}

core_vec3 core_wod_vel_S_mps(double speed_mps, double dir_rad)
{
    return core_vec3_make(-speed_mps * cos(dir_rad), -speed_mps * sin(dir_rad), 0.0);
}

int core_wod_faces(double speed_mps, double dir_rad, int sign[2])
{
    sign[0] = sign[1] = 0;
    if (!(speed_mps > 0.0))
        return 1;
    core_vec3 w = core_wod_vel_S_mps(1.0, dir_rad);
    const double c[2] = {w.x, w.y};
    for (int d = 0; d < 2; d++)
        sign[d] = c[d] > 0.05 ? 1 : c[d] < -0.05 ? -1 : 0;
    return 0;
}

void core_wod_name(double dir_deg, char *buf, size_t n)
{
    double d = core_wod_wrap_deg(dir_deg);
    if (fabs(d) < 1e-9)
        snprintf(buf, n, "head");
    else if (fabs(d - 180.0) < 1e-9)
        snprintf(buf, n, "stern");
    else
        snprintf(buf, n, "%s %g", d > 0 ? "green" : "red", fabs(d));
}

void core_wod_label(double speed_mps, double dir_deg, char *buf, size_t n)
{
    if (fabs(dir_deg) < 0.5)
        snprintf(buf, n, "%.0f kt ahead", speed_mps / CORE_KT_TO_MPS);
    else
        snprintf(buf, n, "%.0f kt %s %.0f", speed_mps / CORE_KT_TO_MPS, dir_deg < 0 ? "red" : "green", fabs(dir_deg));
}
