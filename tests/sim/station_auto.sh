#!/bin/sh
# disim station --auto, the automated pilot as an external station, from
# outside: disim fly flies the UH-60A over the CG-47 in real time (WOD 25 kt
# from ahead, sea state 4, the airwake's free stream: an empty database)
# with one station listed, auto1; disim station --auto
# scenarios/tasks/land_port.ini --id auto1 runs beside it in another
# process, over UDP multicast inside a private network namespace
# (docs/conventions.md). The station puts the flight at the task's start (a
# REPOSITION: the loop starts at the scenario's hover), flies the port-side
# landing on the states it receives and ends once settled on the deck.
# First its flags: refused with exit status 2 naming them; a task file that
# is not there, or no flight to read, exit 1 naming it. Then the landing.
# Checked: the station flew (exit 0, a touchdown said), took the controls
# (the loop says so) and the landing ends on the deck with a sink below
# 2 m/s and within 1 m of the spot, by the station's grading and,
# independently, by the loop's CSV (the first row on the deck: its distance
# from the spot, the sink from the rows before). Real time: about 90 s.
# Without unshare -n or ip it is skipped (exit 77; a failure with CI set,
# tests/skip.sh).
# usage: station_auto.sh DISIM SRC_DIR
set -u
disim=$1
src=$2
. "$src/tests/skip.sh"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
bad() { echo "FAIL: $*"; fail=1; }

# ------------------------------------------------------------------ flags
# expect STATUS TEXT ARGS...: the exit status and a message containing TEXT
expect() {
    want=$1 text=$2
    shift 2
    "$disim" station "$@" < /dev/null > "$tmp/o" 2> "$tmp/e"
    got=$?
    [ "$got" -eq "$want" ] || bad "disim station $*: exit $got, expected $want: $(head -2 "$tmp/e")"
    grep -qF -- "$text" "$tmp/e" || bad "disim station $*: no '$text' in: $(head -2 "$tmp/e")"
}
task=$src/scenarios/tasks/land_port.ini
expect 2 "--keyboard, --device, --script and --auto exclude each other" --auto "$task" --keyboard
expect 2 "--auto: --view, --take-over and --script-absolute do not apply" --auto "$task" --take-over
expect 2 "--auto: expected a value after it" --auto
expect 1 "$tmp/none.ini: No such file or directory" --auto "$tmp/none.ini" --lcm memq:// --wait-s 0.3
expect 1 "no heli_state_t on DISIM_HELI_STATE within 0.3 s" --auto "$task" --lcm memq:// --wait-s 0.3
grep -q "did not fly" "$tmp/o" || bad "a station without a flight: $(cat "$tmp/o")"
expect 1 "--scenario: " --auto "$task" --scenario "$tmp/none.ini" --lcm memq:// --wait-s 0.3

# ------------------------------------------------------- across processes
[ $fail -eq 0 ] || exit 1
unshare -n true 2>/dev/null || skip station_auto "'unshare -n' is not permitted here (needs root or user namespaces)"
command -v ip > /dev/null 2>&1 || skip station_auto "the 'ip' command (iproute2) is missing"

unshare -n sh -c '
ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo || exit 1
disim=$1 src=$2 base=$3
"$disim" station --auto "$src/scenarios/tasks/land_port.ini" --id auto1 --wait-s 30 > "$base.out" 2> "$base.err" &
st=$!
sleep 0.3
"$disim" fly "$src/scenarios/cg47_uh60a_flown.ini" --realtime --duration 150 --wod-speed-kt 25 --wod-dir-deg 0 \
    --sea-state 4 --db "$base.db" --stations auto1 --csv "$base.csv" --log "$base.lcmlog" 2> "$base.fly" & fly=$!
wait $st
echo $? > "$base.st_rc"
kill -TERM $fly 2> /dev/null
wait $fly
echo $? > "$base.rc"
' sh "$disim" "$src" "$tmp/a" || bad "the namespace could not be set up"

src_rc=$(cat "$tmp/a.st_rc" 2>/dev/null || echo none)
[ "$src_rc" = 0 ] || bad "disim station --auto: exit $src_rc: $(tail -3 "$tmp/a.err")"
fly_rc=$(cat "$tmp/a.rc" 2>/dev/null || echo none)
[ "$fly_rc" = 0 ] || bad "disim fly: exit $fly_rc: $(tail -3 "$tmp/a.fly")"
cat "$tmp/a.out"
grep -q "sim control reposition .* in the hover at (-*0.0[0-9], -17.00, -6.00) m in S" "$tmp/a.fly" ||
    bad "the loop was not repositioned at the task's start: $(grep -i reposition "$tmp/a.fly")"
grep "station 'auto1' takes the controls" "$tmp/a.fly" || bad "auto1 did not take the controls: $(tail -3 "$tmp/a.fly")"
# the station's touchdown
set -- $(sed -n 's/^touchdown: t \([0-9.]*\) s, sink \([-0-9.]*\) m\/s, drift [-0-9.]* m\/s, \([0-9.]*\) m from the spot.*settled \([a-z]*\).*/\1 \2 \3 \4/p' "$tmp/a.out")
echo "station: touchdown at ${1:-?} s, sink ${2:-?} m/s, ${3:-?} m from the spot, settled ${4:-?}"
[ -n "${4:-}" ] && awk -v s="$2" -v d="$3" 'BEGIN { exit !(s < 2.0 && s > 0.0 && d < 1.0) }' && [ "$4" = yes ] ||
    bad "the station's landing: sink ${2:-?} m/s, ${3:-?} m from the spot, settled ${4:-?} (expected below 2 m/s, within 1 m, settled)"
# the loop's CSV: the last run (from the reposition, t back to 0), its first
# row on the deck; the sink over the row before (z down: + sinks)
res=$(awk -F, 'NR > 1 { if ($1 + 0 < tp) { n = 0; td = 0 } tp = $1 + 0 }
NR > 1 && !td { if ($21 == 1 && n) { td = 1; t = $1; x = $2; y = $3; sink = ($4 - zp) / ($1 - pt); on = 1 }
    pt = $1; zp = $4; n++ }
NR > 1 && td && $21 == 1 { last = $1 }
END { if (!td) { print "none"; exit } printf "%.3f %.3f %.3f %.3f\n", t, sink, sqrt(x * x + y * y), last - t }' "$tmp/a.csv")
set -- $res
echo "loop CSV: first row on the deck at ${1:-?} s, sink ${2:-?} m/s, ${3:-?} m from the spot, on the deck ${4:-?} s after"
[ "${1:-none}" != none ] && awk -v s="${2:-9}" -v d="${3:-9}" -v on="${4:-0}" 'BEGIN { exit !(s < 2.0 && d < 1.0 && on >= 1.0) }' ||
    bad "the loop's landing: sink ${2:-?} m/s, ${3:-?} m from the spot, ${4:-?} s on the deck (expected below 2 m/s, within 1 m, on the deck for 1 s)"
[ $fail -eq 0 ] && echo "station_auto: all checks passed"
exit $fail
