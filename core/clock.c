/* clock.c -- the monotonic clock for measuring how long work takes
 * (progress rates, time left, wall times in reports). Not for the flight
 * loop's deadlines: sim/pacing.c keeps its own absolute timespecs. */
#include "core.h"

#include <time.h>

double core_monotonic_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}
