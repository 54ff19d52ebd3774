#!/bin/sh
# Every bad-input class of the scenario parser, and every key that no command
# acts on yet (refused_*.ini: the message names file, line, key and why):
# `disim check FILE` must exit 1 and print the error named on the file's
# first line ("; expect: ...").
# Usage: cli_check.sh DISIM_BINARY
set -u
disim=$1
cd "$(dirname "$0")/bad"
pass=0
fail=0
for f in *.ini; do
    [ "$f" = bad_ship_geometry.ini ] && continue
    expect=$(head -n 1 "$f" | sed -n 's/^; expect: //p')
    out=$("$disim" check "$f" 2>&1 >/dev/null)
    rc=$?
    if [ $rc -eq 1 ] && [ -n "$expect" ] && printf '%s' "$out" | grep -qF -- "$expect"; then
        pass=$((pass + 1))
    else
        fail=$((fail + 1))
        echo "FAIL $f: exit $rc, got: $out"
        echo "     expected exit 1 and: $expect"
    fi
done
# Good scenarios resolve and print their configuration.
for s in ../../../scenarios/*.ini; do
    if "$disim" check "$s" >/dev/null 2>&1; then pass=$((pass + 1)); else
        fail=$((fail + 1)); echo "FAIL $s: good scenario rejected"; "$disim" check "$s"; fi
done
# Unknown command and missing argument are usage errors (exit 2).
"$disim" frobnicate >/dev/null 2>&1; [ $? -eq 2 ] && pass=$((pass + 1)) || { fail=$((fail + 1)); echo "FAIL unknown command"; }
"$disim" check >/dev/null 2>&1; [ $? -eq 2 ] && pass=$((pass + 1)) || { fail=$((fail + 1)); echo "FAIL check without file"; }
echo "cli_check: $pass passed, $fail failed"
[ $fail -eq 0 ]
