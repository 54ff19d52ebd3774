# skip.sh -- sourced by the shell tests (POSIX sh) for a test that cannot
# run here (no network namespace, no script(1), no Java):
#   . "$(dirname "$0")/../skip.sh"
#   unshare -n true 2>/dev/null || skip lcm_xproc "'unshare -n' is not permitted here"
# skip NAME REASON prints "NAME: SKIPPED: REASON" and exits 77, CTest's skip
# code (the test sets SKIP_RETURN_CODE 77, so the summary lists it as not
# run, not passed). With the environment variable CI non-empty (.ci/run,
# go.sh test under CI) every such test is one CI is expected to run: the
# same line says the run fails, and skip exits 1. Checked both ways by the
# test skip_helper (tests/skip_check.sh).
skip() {
    if [ -n "${CI:-}" ]; then
        echo "$1: FAILED: cannot run: $2 (CI is set: a test CI is expected to run may not skip)"
        exit 1
    fi
    echo "$1: SKIPPED: $2"
    exit 77
}
