#!/bin/sh
# cli_expect.sh -- a command's exit status and its message: runs COMMAND...,
# passes when it exits with STATUS and its output (stdout and stderr) holds
# MESSAGE (a fixed string). CTest's PASS_REGULAR_EXPRESSION alone ignores the
# exit status, so a command that printed the message and exited 0 passed.
# usage: cli_expect.sh STATUS MESSAGE COMMAND [ARGS...]
want=$1
msg=$2
shift 2
out=$("$@" 2>&1)
rc=$?
printf '%s\n' "$out"
fail=0
[ "$rc" -eq "$want" ] || { echo "cli_expect: exit $rc, expected $want: $*"; fail=1; }
case "$out" in
*"$msg"*) ;;
*) echo "cli_expect: no '$msg' in the output of: $*"; fail=1 ;;
esac
exit $fail
