#!/bin/sh
# skip_check.sh -- the skip helper (tests/skip.sh) both ways: without CI (unset
# or empty) skip exits 77 saying SKIPPED and the reason; with CI set it exits
# 1 saying FAILED and the reason; nothing after skip runs. With DEMO (the
# program check_skip_demo), the same both ways for the C tests' check_skip
# (tests/check.h): 77 and SKIPPED, or 1 and FAILED.
# usage: skip_check.sh SKIP_SH [DEMO]
helper=$1 demo=${2:-}
fail=0
# expect NAME CI_VALUE|unset RC WORD
expect() {
    if [ "$2" = unset ]; then
        out=$(env -u CI sh -c '. "$1"; skip demo "no widget here"; echo "after skip"; exit 0' sh "$helper")
    else
        out=$(env CI="$2" sh -c '. "$1"; skip demo "no widget here"; echo "after skip"; exit 0' sh "$helper")
    fi
    rc=$?
    case "$out" in
    "demo: $4: "*"no widget here"*) ok=1 ;;
    *) ok=0 ;;
    esac
    case "$out" in *"after skip"*) ok=0 ;; esac
    if [ "$rc" -ne "$3" ] || [ "$ok" -ne 1 ]; then
        echo "skip_helper: $1: exit $rc, output '$out' (expected exit $3 and 'demo: $4: ... no widget here')"
        fail=1
    else
        echo "skip_helper: $1: exit $rc, '$out'"
    fi
}
expect "CI unset" unset 77 SKIPPED
expect "CI empty" "" 77 SKIPPED
expect "CI=true" true 1 FAILED
expect "CI=1" 1 1 FAILED
# expect_c NAME CI_VALUE|unset RC WORD
expect_c() {
    if [ "$2" = unset ]; then
        out=$(env -u CI "$demo" 2>&1)
    else
        out=$(env CI="$2" "$demo" 2>&1)
    fi
    rc=$?
    case "$out" in
    *"$4: "*"no widget here"*) ok=1 ;;
    *) ok=0 ;;
    esac
    if [ "$rc" -ne "$3" ] || [ "$ok" -ne 1 ]; then
        echo "skip_helper: check_skip, $1: exit $rc, output '$out' (expected exit $3 and '$4: ... no widget here')"
        fail=1
    else
        echo "skip_helper: check_skip, $1: exit $rc"
    fi
}
if [ -n "$demo" ]; then
    expect_c "CI unset" unset 77 SKIPPED
    expect_c "CI empty" "" 77 SKIPPED
    expect_c "CI=true" true 1 FAILED
fi
exit $fail
