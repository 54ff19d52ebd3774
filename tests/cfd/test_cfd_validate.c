/* test_cfd_validate.c -- the validation cases of `disim validate`; argv[1]
 * names the case. Without --full: the reduced grids (small = 1) and the
 * looser tolerances stated in cfd/validate.c, the CI set (`ctest -R cfd`).
 * With --full: the full grids at the documents' tolerances, the set CTest
 * labels `validation` (`ctest -L validation`; docs/validation/cfd.md).
 * Every figure must pass, a converged check included. */
#include "cfd.h"
#include "check.h"

#include <stdio.h>
#include <string.h>

int main(int argc, char **argv)
{
    int full = argc == 3 && !strcmp(argv[2], "--full");
    if (argc < 2 || argc > 3 || (argc == 3 && !full)) {
        fprintf(stderr, "usage: test_cfd_validate CASE [--full]\n");
        return 2;
    }
    cfd_report rep;
    core_err err = {0};
    int rc = cfd_validate(argv[1], !full, NULL, NULL, NULL, NULL, NULL, &rep, &err);
    CHECK(rc == 0);
    if (rc)
        fprintf(stderr, "%s\n", err.msg);
    CHECK(rep.n > 0);
    CHECK(rep.passed + rep.failed == rep.n);
    for (int i = 0; i < rep.n; i++) {
        printf("%-46s measured %10.4f reference %10.4f tol %8.4f %s\n", rep.c[i].name, rep.c[i].measured,
               rep.c[i].reference, rep.c[i].tol, rep.c[i].pass ? "pass" : "FAIL");
        CHECK(rep.c[i].pass);
    }
    printf("%s%s: %d passed, %d failed, %.1f s\n", argv[1], full ? " (full)" : "", rep.passed, rep.failed, rep.wall_s);
    char name[80];
    snprintf(name, sizeof name, "test_cfd_validate %s%s", argv[1], full ? " --full" : "");
    return check_done(name);
}
