#!/bin/sh
# bench_flown.sh -- the flown SHOL's benchmarks (not in ctest),
# on a database that already holds the scenario's ship-only fields:
#   1. one landing flown headless by the automated pilot (`disim fly
#      --pilot auto`) in 25 kt from ahead, sea state 4: its wall time
#      per minute flown (the target: under 1 s);
#   2. the whole flown envelope (`disim shol --method pilot`): its wall
#      time (the target: under 30 minutes on 2 cores), the
#      flights, the time flown and the wall time per minute flown.
# The database is only read: both commands find every field READY.
# Usage: bench/shol/bench_flown.sh DISIM SCENARIO DB [--grid G] [--seeds N] [--task FILE] [--keep DIR]
#   e.g. bench/shol/bench_flown.sh build/app/disim scenarios/cg47_uh60a_flown.ini out/airwake-db
set -u
[ $# -ge 3 ] || { echo "usage: $0 DISIM SCENARIO DB [--grid G] [--seeds N] [--task FILE] [--keep DIR]" >&2; exit 2; }
disim=$1 scen=$2 db=$3
shift 3
grid="" seeds="" task="$(dirname "$scen")/tasks/land_uh60a.ini" keep=""
while [ $# -gt 0 ]; do
    case "$1" in
    --grid) grid="--grid $2"; shift 2 ;;
    --seeds) seeds="--seeds $2"; shift 2 ;;
    --task) task=$2; shift 2 ;;
    --keep) keep=$2; shift 2 ;;
    *) echo "$0: unknown argument '$1'" >&2; exit 2 ;;
    esac
done
if [ -n "$keep" ]; then
    tmp=$keep
    mkdir -p "$tmp" || exit 1
else
    tmp=$(mktemp -d /tmp/bench_flown_XXXXXX)
fi
now() { date +%s.%N; }
t0=$(now)
"$disim" fly "$scen" --wod-speed-kt 25 --wod-dir-deg 0 --sea-state 4 --pilot auto --task "$task" --db "$db" \
    2> "$tmp/fly.log" || { echo "the landing failed"; cat "$tmp/fly.log"; exit 1; }
t1=$(now)
flown=$(sed -n 's/.*touchdown .* at \([0-9.]*\) s (descent.*/\1/p' "$tmp/fly.log")
[ -n "$flown" ] || flown=$(sed -n 's/.*task .* at \([0-9.]*\) s.*/\1/p' "$tmp/fly.log" | tail -1)
awk -v a="$t0" -v b="$t1" -v f="$flown" 'BEGIN { w = b - a; printf "one landing: %.1f s flown in %.2f s of wall time: %.2f s per minute flown\n", f, w, 60 * w / f }'
t2=$(now)
"$disim" shol "$scen" $grid --method pilot --task "$task" $seeds -o "$tmp/out" --db "$db" > "$tmp/shol.csv" 2> "$tmp/shol.log" \
    || { echo "the flown envelope failed"; tail -5 "$tmp/shol.log"; exit 1; }
t3=$(now)
grep -q "started an airwake builder" "$tmp/shol.log" && echo "note: a field was missing and was built: the time includes CFD"
j="$tmp/out/shol_flown.json"
fl=$(sed -n 's/^  "flights": \([0-9]*\),/\1/p' "$j")
fs=$(sed -n 's/^  "flown_s": \([0-9.]*\),/\1/p' "$j")
ws=$(sed -n 's/^  "wall_s": \([0-9.]*\),/\1/p' "$j")
awk -v a="$t2" -v b="$t3" -v n="$fl" -v f="$fs" -v w="$ws" 'BEGIN { printf "flown envelope: %.1f s of wall time (the flights %.1f s), %d flights, %.0f s flown: %.2f s per minute flown\n", b - a, w, n, f, 60 * w / f }'
cat "$tmp/shol.csv"
[ -n "$keep" ] || rm -rf "$tmp"
