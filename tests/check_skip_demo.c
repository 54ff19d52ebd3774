/* check_skip_demo.c -- check.h's check_skip for skip_check.sh: one check
 * that passes, then a part that cannot run ("no widget here"). Exits 77
 * without CI (check_done after a skip, nothing failed) and 1 with CI set
 * (the skip counted as a failure). */
#include "check.h"

int main(void)
{
    CHECK(1 + 1 == 2);
    check_skip("demo: no widget here");
    return check_done("check_skip_demo");
}
