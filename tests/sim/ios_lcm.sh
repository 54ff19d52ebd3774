#!/bin/sh
# disim ios against a disim fly --realtime across processes, inside a
# private network namespace so that nothing leaves loopback
# (docs/conventions.md): each instructor's command is answered (ok, or
# refused with its reason, exit 1), its effect is in the flight's CSV
# (a reposition, the deck), a script runs, and the run's log, its
# controls replayed --fast, flies the live trajectory byte for byte (the
# WOD's speed and the turbulence changed in flight, a snapshot restored).
# Skipped (77) without a namespace or ip; a failure with CI set
# (tests/skip.sh).
# Usage: ios_lcm.sh DISIM SOURCE_DIR
set -u
. "$(dirname "$0")/../skip.sh"
unshare -rn true 2>/dev/null || unshare -n true 2>/dev/null \
    || skip ios_lcm "'unshare -n' is not permitted here (needs root or user namespaces)"
command -v ip >/dev/null 2>&1 || skip ios_lcm "the 'ip' command (iproute2) is missing"
ns="unshare -n"
unshare -n true 2>/dev/null || ns="unshare -rn"
tmp=$(mktemp -d /tmp/disim_ios_lcm_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
exec $ns sh -c '
disim=$1 src=$2 tmp=$3
ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo || { echo "FAIL: namespace setup"; exit 1; }
fail=0 pass=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $1"; fail=$((fail + 1)); }
scen="$src/tests/sim/data/loop_a.ini"
# ios CMD EXPECT_RC PATTERN: one command, its exit status and its answer
ios() {
    out=$("$disim" ios --timeout-s 10 --cmd "$1" 2>&1); rc=$?
    echo "ios $1 -> $out (exit $rc)"
    [ "$rc" = "$2" ] && printf "%s\n" "$out" | grep -q -- "$3" && ok || bad "ios $1: expected exit $2 and $3"
}
"$disim" fly "$scen" --realtime --duration 20 --db "$tmp/db" --log "$tmp/run.lcmlog" --csv "$tmp/live.csv" \
    2> "$tmp/live.log" & fly=$!
# the loop answers once it is up
for i in 1 2 3 4 5 6 7 8 9 10; do
    "$disim" ios --timeout-s 1 --cmd status > "$tmp/st.txt" 2>&1 && break
done
cat "$tmp/st.txt"
grep -q "status: loop_a running" "$tmp/st.txt" && ok || bad "no status from the loop"
ios freeze 0 "^ok: frozen at t = "
ios status 0 "loop_a frozen"
ios resume 0 "^ok: running from"
# refused, with the reason; the flight goes on
ios "reposition 0 0 1" 1 "^refused: reposition refused: (0.0, 0.0, 1.0) m is inside the ship"
ios "reposition 0 200 40" 1 "under the sea"
ios "reposition nan 0 -10" 1 "not finite"
ios "wod 200 0" 1 "^refused: set wod refused: WOD"
ios "sea 9" 1 "sea state 9: expected 0 to 6"
ios "restore nope" 1 "no snapshot .nope."
ios "snap two.words!" 1 "snapshot name"
"$disim" ios --timeout-s 2 --cmd "fly away" > "$tmp/bad.txt" 2>&1 && bad "a bad command accepted" || ok
grep -q "not a command" "$tmp/bad.txt" && ok || bad "a bad command not said"
# accepted, and their effect
ios "reposition 0 30 -10" 0 "^ok: reposition: loop_a in the hover at (0.00, 30.00, -10.00) m"
ios "snap a" 0 "^ok: snapshot .a. at t = "
sleep 1
ios "wod 15 20" 0 "(15.0 kt from 20 deg)"
ios "sea 3" 0 "(sea state 3)"
ios "wod 20 20" 0 "^ok: in flight at t = .*: WOD 20.0 kt from 20 deg (the air re-scaled)"
ios "turb on" 0 "^ok: in flight at t = .*: turbulence on"
ios "restore a" 0 "^ok: restored .a.: t = "
ios "reset deck 10" 0 "on the deck"
sleep 1
ios status 0 "on deck"
ios "reset hover" 0 "^ok: reset hover: loop_a in the hover"
printf "freeze\nwait 0.2\nstatus # frozen\nresume\n" > "$tmp/script.txt"
"$disim" ios --script "$tmp/script.txt" > "$tmp/script.out" 2>&1 && grep -q "loop_a frozen" "$tmp/script.out" \
    && ok || { bad "the script"; cat "$tmp/script.out"; }
wait $fly && ok || bad "disim fly failed"
cat "$tmp/live.log"
# the log says each control and its time; the CSV has the reposition and the deck
grep -q "sim control set sea (seq [0-9]*): .* (applied in [0-9.]* s)" "$tmp/live.log" && ok || bad "no log line of the sea state"
awk -F, "NR > 1 && \$1 < 0.05 && \$3 > 29.9 && \$3 < 30.1 && \$4 > -10.1 && \$4 < -9.9 { f = 1 } END { exit !f }" \
    "$tmp/live.csv" && ok || bad "the reposition is not in the CSV"
awk -F, "NR > 1 && \$1 < 0.05 && \$4 > -3 && \$4 < 0 { f = 1 } END { exit !f }" "$tmp/live.csv" \
    && ok || bad "the deck start is not in the CSV"
# the instructor session replayed from its log: the same flight
"$disim" fly "$scen" --fast --duration 20 --db "$tmp/db" --replay-inputs "$tmp/run.lcmlog" --csv "$tmp/fast.csv" \
    2> "$tmp/fast.log" && ok || { bad "replay --fast failed"; cat "$tmp/fast.log"; }
cmp -s "$tmp/live.csv" "$tmp/fast.csv" && ok || bad "the replay of the session differs from the live run"
# the rate limit of world changes set on the command line: one at once, the
# next after 1000 s of run time
"$disim" fly "$scen" --change-burst 0 --fast --duration 1 --no-lcm > "$tmp/lim.txt" 2>&1
[ $? -eq 1 ] && grep -q -- "--change-burst: expected a whole number in \[1, 1000\]" "$tmp/lim.txt" && ok || { bad "--change-burst 0 not refused"; cat "$tmp/lim.txt"; }
"$disim" fly "$scen" --realtime --duration 8 --db "$tmp/db" --change-burst 1 --change-interval-s 1000 \
    2> "$tmp/lim.log" & fly=$!
for i in 1 2 3 4 5 6 7 8 9 10; do
    "$disim" ios --timeout-s 1 --cmd status > /dev/null 2>&1 && break
done
ios "reset hover" 0 "^ok: reset hover"
ios "reset deck" 1 "rate limit: at most 1 world changes at once and one more every 1000 s"
wait $fly && ok || bad "disim fly --change-burst 1 failed"
echo "ios_lcm: $pass passed, $fail failed"
# every check ran (a script cut short by a quoting slip must not pass)
[ "$fail" -eq 0 ] && [ "$pass" -eq 34 ]
' sh "$1" "$2" "$tmp"
