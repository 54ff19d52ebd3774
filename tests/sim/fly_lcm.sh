#!/bin/sh
# disim fly across processes, inside a private network namespace so that
# nothing leaves loopback (docs/conventions.md): a station process (fly_lcm_peer
# pilot) flies the helicopter, blended in over 1 s with the status's flag
# raised meanwhile, its collective step climbs; killed, the
# input is held and the flag raised within --hold-after-s (from the run's
# LCM log); the log replayed by lcm-logplayer reaches a listener that
# receives and decodes every message; --fast and --realtime fed the log's
# inputs (--replay-inputs) fly the live run's trajectory, identical.
# Skipped (77) without a namespace, ip or lcm-logplayer; a failure with CI
# set (tests/skip.sh).
# Usage: fly_lcm.sh DISIM PEER SOURCE_DIR
set -u
. "$(dirname "$0")/../skip.sh"
unshare -rn true 2>/dev/null || unshare -n true 2>/dev/null \
    || skip fly_lcm "'unshare -n' is not permitted here (needs root or user namespaces)"
command -v ip >/dev/null 2>&1 || skip fly_lcm "the 'ip' command (iproute2) is missing"
command -v lcm-logplayer >/dev/null 2>&1 || skip fly_lcm "lcm-logplayer (liblcm-bin) is missing"
ns="unshare -n"
unshare -n true 2>/dev/null || ns="unshare -rn"
tmp=$(mktemp -d /tmp/disim_fly_lcm_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
exec $ns sh -c '
disim=$1 peer=$2 src=$3 tmp=$4
ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo || { echo "FAIL: namespace setup"; exit 1; }
fail=0 pass=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $1"; fail=$((fail + 1)); }
val() { sed -n "s/^$1 //p" "$2"; }
scen="$src/tests/sim/data/loop_a.ini"
# the live run: 6 s in real time, a station for about 3 s, then killed
"$disim" fly "$scen" --realtime --duration 6 --hold-after-s 0.5 --log "$tmp/run.lcmlog" --csv "$tmp/live.csv" \
    2> "$tmp/live.log" & fly=$!
"$peer" pilot A 30 5 & st=$!
sleep 3.5
kill -KILL $st
wait $fly && ok || { bad "disim fly (live) failed"; cat "$tmp/live.log"; }
cat "$tmp/live.log"
[ -s "$tmp/run.lcmlog" ] && ! ls "$tmp"/*.tmp* >/dev/null 2>&1 && ok || bad "no log, or a temporary one left"
"$peer" climb "$tmp/run.lcmlog" > "$tmp/climb.txt"; cat "$tmp/climb.txt"
awk "\$1 == \"climb_m\" { exit !(\$2 > 0.5) }" "$tmp/climb.txt" && ok || bad "the collective step did not climb 0.5 m"
"$peer" held "$tmp/run.lcmlog" 0.5 > "$tmp/held.txt" && ok || bad "the input not held, or the flag not within 0.5 s + 2 steps"
cat "$tmp/held.txt"
"$peer" blend "$tmp/run.lcmlog" > "$tmp/blend.txt" && ok || bad "the first station message not blended in over 1 s, FLAG_CONTROLS_BLENDING"
cat "$tmp/blend.txt"
# the log played back to a listener: every message, decoded
"$peer" logcount "$tmp/run.lcmlog" > "$tmp/logcount.txt"
"$peer" listen 30 > "$tmp/listen.txt" & ls=$!
sleep 0.3
lcm-logplayer "$tmp/run.lcmlog" > /dev/null 2>&1 || bad "lcm-logplayer failed"
wait $ls
cmp -s "$tmp/logcount.txt" "$tmp/listen.txt" && ok || { bad "the listener did not receive the log"; paste "$tmp/logcount.txt" "$tmp/listen.txt"; }
[ "$(val bad "$tmp/listen.txt")" = 0 ] && [ "$(val DISIM_PILOT_INPUT "$tmp/listen.txt")" -gt 100 ] \
    && [ "$(val DISIM_HELI_STATE "$tmp/listen.txt")" -eq 300 ] && [ "$(val DISIM_SHIP_STATE "$tmp/listen.txt")" -eq 300 ] \
    && ok || { bad "expected 300 heli and ship states at 50 Hz, over 100 pilot inputs, none bad"; cat "$tmp/listen.txt"; }
# the log'"'"'s inputs, replayed as fast as it can and in real time: the live trajectory
"$disim" fly "$scen" --fast --duration 6 --replay-inputs "$tmp/run.lcmlog" --csv "$tmp/fast.csv" 2> "$tmp/fast.log" \
    && ok || { bad "replay --fast failed"; cat "$tmp/fast.log"; }
"$disim" fly "$scen" --realtime --duration 6 --replay-inputs "$tmp/run.lcmlog" --csv "$tmp/rt.csv" 2> "$tmp/rt.log" \
    && ok || { bad "replay --realtime failed"; cat "$tmp/rt.log"; }
cmp -s "$tmp/fast.csv" "$tmp/rt.csv" && ok || bad "--fast and --realtime replays differ"
cmp -s "$tmp/live.csv" "$tmp/fast.csv" && ok || bad "the replay differs from the live run"
echo "fly_lcm: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
' sh "$1" "$2" "$3" "$tmp"
