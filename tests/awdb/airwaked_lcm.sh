#!/bin/sh
# disim airwaked end to end, inside a private network namespace: an LCM
# request is queued, built by the embedded CFD engine (coarse SFS2, a few
# iterations: this checks the path, not the physics), committed with its
# checksum and announced READY on LCM; a bad request is refused naming the
# field, and so is a loaded-disk request (the message has no blade loads:
# it must not be built as a uniform disk), and a request whose string lacks
# its NUL is refused before decoding; the database holds one verified
# field and no temporaries.
# Usage: airwaked_lcm.sh DISIM AW_CLIENT SOURCE_DIR
# Where unshare or ip is missing: skipped (exit 77), and a failure with CI
# set (tests/skip.sh).
set -u
disim=$1 client=$2 src=$3
. "$src/tests/skip.sh"
unshare -n true 2>/dev/null || skip airwaked_lcm "'unshare -n' is not permitted here (needs root or user namespaces)"
command -v ip >/dev/null 2>&1 || skip airwaked_lcm "the 'ip' command (iproute2) is missing"
db=$(mktemp -d /tmp/disim_airwaked_XXXXXX)
exec unshare -n sh -c '
ip link set lo up; ip link set lo multicast on; ip route add 224.0.0.0/4 dev lo
disim=$1 client=$2 src=$3 db=$4
"$disim" airwaked "$db" --jobs 1 --ships "$src/scenarios/ships" --max-iter 10 > "$db/daemon.log" 2>&1 &
pid=$!
fail=0
"$client" 5 20 bad || fail=1
"$client" 5 20 loaded || fail=1
"$client" 5 20 raw || fail=1
"$client" 7.5 900 || fail=1
kill -TERM $pid; wait $pid; rc=$?
[ $rc -eq 0 ] || { echo "airwaked exited $rc"; fail=1; }
n=$(ls "$db"/fields/*.h5 2>/dev/null | wc -l); s=$(ls "$db"/fields/*.sum 2>/dev/null | wc -l)
t=$(ls -a "$db"/fields | grep -c "^\.tmp")
echo "airwaked_lcm: $n field(s), $s checksum(s), $t temporaries"
[ "$n" -eq 1 ] && [ "$s" -eq 1 ] && [ "$t" -eq 0 ] || fail=1
grep -q "ready" "$db/daemon.log" || { echo "no ready line in the log"; fail=1; }
[ $fail -eq 0 ] || cat "$db/daemon.log"
rm -rf "$db"
exit $fail
' sh "$disim" "$client" "$src" "$db"
