#!/bin/sh
# skip_check.sh -- the skip helper (tests/skip.sh) both ways: without CI (unset
# or empty) skip exits 77 saying SKIPPED and the reason; with CI set it exits
# 1 saying FAILED and the reason; nothing after skip runs.
# usage: skip_check.sh SKIP_SH
helper=$1
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
exit $fail
