#!/bin/sh
# Flown trajectories, byte for byte: every way disim flies a flight (--fast,
# real time through the loop, on the deck, the automated pilot straight and
# through the loop, the replay pilot, a crash, the flown SHOL's automated and
# replay flights) writes its outputs, and their SHA-256 sums must equal
# tests/sim/data/trajectories.sha256, recorded from the code before the
# flight runner was shared. A change that moves a trajectory fails here;
# one that means to (a model change) records the sums anew:
#   trajectories.sh DISIM SOURCE_DIR --record
# Usage: trajectories.sh DISIM SOURCE_DIR [--record]
set -u
disim=$1 src=$2 record=${3:-}
tmp=$(mktemp -d /tmp/disim_traj_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
sums=$src/tests/sim/data/trajectories.sha256
fail=0
run() { # NAME ARGS...: one flight, its stderr kept for a failure
    name=$1
    shift
    "$disim" "$@" 2> "$tmp/$name.err" > "$tmp/$name.out"
    rc=$?
    [ $rc -eq 0 ] || [ $rc -eq 3 ] || { echo "FAIL: $name: exit $rc"; cat "$tmp/$name.err"; fail=1; }
}
sc=$src/scenarios/cg47_uh60a.ini
args="$sc --duration 2 --wod-speed-kt 20 --wod-dir-deg -30 --sea-state 4 --ship-speed-kt 10 --db $tmp/db"
run hover fly $args --fast --csv "$tmp/hover.csv"
run hover_rt fly $args --realtime --lcm memq:// --csv "$tmp/hover_rt.csv"
run deck fly $args --fast --start deck --csv "$tmp/deck.csv"
port="$sc --wod-speed-kt 25 --wod-dir-deg 0 --db $tmp/db --sea-state 4 --seed 3 --pilot auto --task $src/scenarios/tasks/land_port.ini"
run auto fly $port --csv "$tmp/auto.csv"
run auto_log fly $port --csv "$tmp/auto_log.csv" --log "$tmp/auto_log.lcm"
run replay fly "$sc" --wod-speed-kt 25 --wod-dir-deg 0 --db "$tmp/db" --sea-state 4 --seed 3 --pilot replay "$tmp/auto_log.lcm" \
    --csv "$tmp/replay.csv"
run crash fly "$sc" --wod-speed-kt 0 --wod-dir-deg 0 --db "$tmp/db" --pilot auto --task "$src/tests/sim/data/into_hangar.ini" \
    --csv "$tmp/crash.csv"
scen=$src/tests/shol/data/pilot_cg47.ini
run flown shol "$scen" --method pilot --task "$src/scenarios/tasks/land_uh60a.ini" --seeds 2 --speed-max-kmh 0 \
    -o "$tmp/flown" --db "$tmp/db"
run flown_replay shol "$scen" --method pilot --task "$tmp/auto_log.lcm" --seeds 1 --speed-max-kmh 0 -o "$tmp/flown_replay" \
    --db "$tmp/db"
cp "$tmp/flown/shol_flown_points.csv" "$tmp/flown_points.csv" 2> /dev/null
cp "$tmp/flown_replay/shol_flown_points.csv" "$tmp/flown_replay_points.csv" 2> /dev/null
(cd "$tmp" && sha256sum hover.csv hover_rt.csv deck.csv auto.csv auto_task.csv auto_task.json auto_log.csv replay.csv \
    crash.csv crash_task.json flown_points.csv flown_replay_points.csv) > "$tmp/now.sha256" 2> "$tmp/sum.err" \
    || { echo "FAIL: an output is missing"; cat "$tmp/sum.err"; fail=1; }
if [ "$record" = "--record" ]; then
    [ $fail -eq 0 ] && cp "$tmp/now.sha256" "$sums" && echo "recorded $sums" && exit 0
    exit 1
fi
if ! diff "$sums" "$tmp/now.sha256" > "$tmp/diff"; then
    echo "FAIL: trajectories differ from the recorded ones:"
    cat "$tmp/diff"
    fail=1
fi
n=$(wc -l < "$sums")
same=$(sort "$sums" "$tmp/now.sha256" | uniq -d | wc -l)
echo "$same passed, $((n - same)) failed"
exit $fail
