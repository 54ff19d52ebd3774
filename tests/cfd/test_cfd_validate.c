/* test_cfd_validate.c -- the validation cases of `disim validate` on the
 * reduced grids (small = 1) with the tolerances stated in cfd/validate.c;
 * argv[1] names the case. Every figure must pass. */
#include "cfd.h"
#include "check.h"

#include <stdio.h>

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: test_cfd_validate CASE\n");
        return 2;
    }
    cfd_report rep;
    core_err err = {{0}};
    int rc = cfd_validate(argv[1], 1, NULL, NULL, NULL, NULL, NULL, &rep, &err);
    CHECK(rc == 0);
    if (rc)
        fprintf(stderr, "%s\n", err.msg);
    CHECK(rep.n > 0);
    for (int i = 0; i < rep.n; i++) {
        printf("%-46s measured %10.4f reference %10.4f tol %8.4f %s\n", rep.c[i].name, rep.c[i].measured,
               rep.c[i].reference, rep.c[i].tol, rep.c[i].pass ? "pass" : "FAIL");
        CHECK(rep.c[i].pass);
    }
    char name[64];
    snprintf(name, sizeof name, "test_cfd_validate %s", argv[1]);
    return check_done(name);
}
