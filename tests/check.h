/* check.h -- the tests' assertions: each failure prints file:line and the
 * values, the run goes on, and the exit status counts the failures. */
#ifndef DISIM_TEST_CHECK_H
#define DISIM_TEST_CHECK_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int check_failures = 0;
static int check_count = 0;

#define CHECK(cond)                                                                     \
    do {                                                                                \
        check_count++;                                                                  \
        if (!(cond)) {                                                                  \
            check_failures++;                                                           \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);    \
        }                                                                               \
    } while (0)

#define CHECK_NEAR(a, b, tol)                                                           \
    do {                                                                                \
        double check_a_ = (a), check_b_ = (b);                                          \
        check_count++;                                                                  \
        if (!(fabs(check_a_ - check_b_) <= (tol))) {                                    \
            check_failures++;                                                           \
            fprintf(stderr, "%s:%d: CHECK_NEAR failed: %s = %.9g, %s = %.9g, tol %g\n", \
                    __FILE__, __LINE__, #a, check_a_, #b, check_b_, (double)(tol));     \
        }                                                                               \
    } while (0)

static int check_skipped = 0;

/* A part of the test that cannot run here (what says why): without the
 * environment variable CI (unset or empty) it is skipped, and check_done
 * returns 77 (CTest's SKIP_RETURN_CODE, set on the test) when nothing
 * failed; with CI set it is a failure (CI installs everything a test needs:
 * a test CI runs may not skip), as tests/skip.sh does for the scripts. */
static inline void check_skip(const char *what)
{
    const char *ci = getenv("CI");
    if (ci && *ci) {
        check_failures++;
        fprintf(stderr, "FAILED: cannot run: %s (CI is set: a test CI is expected to run may not skip)\n", what);
    } else {
        check_skipped++;
        printf("SKIPPED: %s\n", what);
    }
}

/* Print a summary and return the exit status for main(): 1 when a check
 * failed, 77 when none did but a part was skipped, 0 otherwise. */
static inline int check_done(const char *name)
{
    printf("%s: %d checks, %d failed%s\n", name, check_count, check_failures,
           check_skipped ? ", parts SKIPPED (exit 77)" : "");
    return check_failures ? 1 : check_skipped ? 77 : 0;
}

#endif
