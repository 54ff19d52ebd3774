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
# Files that are not a scenario's text: each refused with what it is.
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
expect_check() { # FILE EXPECTED-MESSAGE
    out=$(timeout 20 "$disim" check "$1" 2>&1 >/dev/null)
    rc=$?
    if [ $rc -eq 1 ] && printf '%s' "$out" | grep -qF -- "$2"; then
        pass=$((pass + 1))
    else
        fail=$((fail + 1))
        echo "FAIL check $1: exit $rc, got: $out"
        echo "     expected exit 1 and: $2"
    fi
}
truncate -s 200M "$tmp/zeros.ini"
expect_check "$tmp/zeros.ini" "zeros.ini: 209715200 bytes, larger than the 16777216 bytes"
head -c 4096 /dev/zero > "$tmp/small_zeros.ini"
expect_check "$tmp/small_zeros.ini" "small_zeros.ini:1:1: a NUL byte (a binary file?): expected text"
mkfifo "$tmp/fifo.ini"
expect_check "$tmp/fifo.ini" "fifo.ini: a FIFO, expected a regular file"
expect_check /dev/zero "/dev/zero: a character device, expected a regular file"
expect_check ../data "../data: a folder, expected a regular file"
sed "s|^aircraft = .*|aircraft = $tmp/fifo.ini|" missing_file.ini > "$tmp/aircraft_fifo.ini"
expect_check "$tmp/aircraft_fifo.ini" "fifo.ini: a FIFO, expected a regular file"
expect_check ../../../scenarios/tasks/land_stern.ini \
    "land_stern.ini: a task file ([task]): check it through the scenario that names it"
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
