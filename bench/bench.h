/* bench.h -- what the benchmarks share (private to bench/): the process's
 * CPU time and the median of repeats. */
#ifndef DISIM_BENCH_H
#define DISIM_BENCH_H

#include <stdlib.h>
#include <time.h>

/* Seconds of CPU time this process has used. */
static inline double bench_cpu_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static inline int bench_cmpd(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The median of v[0..n) (v is sorted in place; the upper one for even n). */
static inline double bench_median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, bench_cmpd);
    return v[n / 2];
}

#endif
