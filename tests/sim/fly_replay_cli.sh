#!/bin/sh
# disim fly --pilot replay LOG: the replay pilot (sim/pilot_replay.c)
# re-flies a logged run headless. The automated pilot's port-side deck
# landing (scenarios/tasks/land_port.ini, calm air, flown --fast, 48.16 s
# to touchdown and on the deck) logged with --log is re-flown in 10 kt
# from green 30: it flies the log's whole length from where the logged run
# started (within 0.01 m), reports its errors overall and per phase
# (hover, translate, descend, on deck), and tracks the landing: from the
# reference rms at most 0.45 m and max at most 0.9 m, heading within 5 deg
# (measured with the SAS on as logged, the replay's integrals and its
# steady trims: 0.219 m, 0.433 m at 31.69 s, 0.50 deg; the tolerances
# kept from the SAS-off replay's 0.281 m, 0.578 m, 2.13 deg, about 1.5
# times those), ending on the deck within 0.25 m of where the logged run
# ended (measured 0.079 m);
# the SAS flown as the log says the
# recorded run had it (on for the automated pilot's, off for a run flown
# --sas off); --feed-controls flies too, and a
# scenario's [pilot] type = replay flies the same CSV as the flag. The
# same landing flown in 25 kt from ahead in sea state 4 (seed 3, free
# stream), logged and replayed in the same conditions, tracks it within
# rms 0.26 m and max 0.59 m: halfway between the replay pilot taking out
# the steady moments and vertical force (sim/pilot_replay.c, "The steady
# trims": 0.205 m, 0.443 m) and not (0.316 m, 0.734 m). Bad logs
# (missing, not a log, truncated, without a heli_state_t) and bad flags
# are refused, naming what, with a non-zero exit and nothing written.
# Usage: fly_replay_cli.sh DISIM SOURCE_DIR
set -u
disim=$1 src=$2
tmp=$(mktemp -d /tmp/disim_fly_replay_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail=0 pass=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $1"; fail=$((fail + 1)); }
scen="$src/scenarios/cg47_uh60a.ini"
"$disim" fly "$scen" --fast --wod-speed-kt 0 --wod-dir-deg 0 --db "$tmp/db" --pilot auto \
    --task "$src/scenarios/tasks/land_port.ini" --log "$tmp/rec.log" --csv "$tmp/rec.csv" 2> "$tmp/rec.err" \
    && [ -s "$tmp/rec.log" ] && grep -q "fly: touchdown " "$tmp/rec.err" && ok \
    || { bad "the landing was not flown and logged"; cat "$tmp/rec.err"; }
args="$scen --wod-speed-kt 10 --wod-dir-deg 30 --db $tmp/db"
"$disim" fly $args --pilot replay "$tmp/rec.log" --csv "$tmp/rep.csv" 2> "$tmp/rep.err" && ok \
    || { bad "fly --pilot replay failed"; cat "$tmp/rep.err"; }
cat "$tmp/rep.err"
grep -q "the replay pilot re-flies .*rec.log ([0-9]* states, 48.16 s" "$tmp/rep.err" && ok \
    || { bad "no start line for the 48.16 s landing"; cat "$tmp/rep.err"; }
# the SAS as the log says the run had it: the automated pilot flew the aircraft file's (engaged)
grep -q "fly: the SAS on; the log's run flew it on" "$tmp/rep.err" && ok || bad "the replay did not fly the logged SAS (on)"
"$disim" fly "$scen" --fast --duration 1 --sas off --wod-speed-kt 0 --wod-dir-deg 0 --db "$tmp/db" --log "$tmp/off.log" \
    2> /dev/null && "$disim" fly $args --pilot replay "$tmp/off.log" 2> "$tmp/off.err" \
    && grep -q "fly: the SAS off; the log's run flew it off" "$tmp/off.err" && ok \
    || { bad "the replay did not fly the logged SAS (off)"; cat "$tmp/off.err"; }
# fly: replay to 48.16 s: from the reference rms R m, max M m at T s, heading max H deg; ...
line=$(grep "fly: replay to 48.16 s: from the reference rms [0-9.]* m, max [0-9.]* m at [0-9.]* s, heading max [0-9.]* deg" \
    "$tmp/rep.err")
[ -n "$line" ] && ok || { bad "no report of the errors"; cat "$tmp/rep.err"; }
echo "$line" | awk '{ for (i = 1; i <= NF; i++) { if ($i == "rms") r = $(i + 1); if ($i == "max" && $(i - 1) == "m,") m = $(i + 1);
        if ($i == "heading") h = $(i + 2) } exit !(r != "" && r + 0 <= 0.45 && m + 0 <= 0.9 && h + 0 <= 5.0) }' && ok \
    || bad "the replay did not track the landing (rms <= 0.45 m, max <= 0.9 m, heading <= 5 deg): $line"
for phase in hover translate descend "on deck"; do
    grep -q "fly: replay $phase: [0-9.]* s, rms" "$tmp/rep.err" && ok || bad "no report of the $phase phase"
done
[ "$(wc -l < "$tmp/rep.csv")" -eq "$(wc -l < "$tmp/rec.csv")" ] && ok \
    || bad "expected as many rows as the logged run's CSV (50 Hz over the log's 48.16 s)"
# the squared distance between the two CSVs' positions in S (columns 2-4) on line LINE is below D2
near() { # LINE D2
    awk -F, -v line="$1" -v d2="$2" 'NR == FNR { if (FNR == line) { x = $2; y = $3; z = $4 }; next }
        FNR == line { d = ($2 - x) ^ 2 + ($3 - y) ^ 2 + ($4 - z) ^ 2; found = 1 }
        END { exit !(found && d < d2) }' "$tmp/rec.csv" "$tmp/rep.csv"
}
near 2 1e-4 && ok || { bad "the replay did not start within 0.01 m of where the logged run started"; sed -n 2p "$tmp/rec.csv" "$tmp/rep.csv"; }
near "$(wc -l < "$tmp/rec.csv")" 0.0625 && ok \
    || { bad "the replay did not end within 0.25 m of the logged run's end"; tail -n 1 "$tmp/rec.csv" "$tmp/rep.csv"; }
# on the deck at the end (the CSV's on_deck column), as the logged run
col=$(head -n 1 "$tmp/rep.csv" | tr , '\n' | grep -n '^on_deck$' | cut -d: -f1)
[ -n "$col" ] && [ "$(tail -n 1 "$tmp/rep.csv" | cut -d, -f"$col")" = 1 ] \
    && [ "$(tail -n 1 "$tmp/rec.csv" | cut -d, -f"$col")" = 1 ] && ok || bad "the replay did not end on the deck"
"$disim" fly $args --pilot replay "$tmp/rec.log" --feed-controls 2> "$tmp/ff.err" && grep -q "fed forward" "$tmp/ff.err" \
    && ok || { bad "--feed-controls failed"; cat "$tmp/ff.err"; }
# 25 kt from ahead, sea state 4: logged and replayed in the same conditions
ss4="$scen --wod-speed-kt 25 --wod-dir-deg 0 --sea-state 4 --seed 3 --db $tmp/db"
"$disim" fly $ss4 --pilot auto --task "$src/scenarios/tasks/land_port.ini" --log "$tmp/ss4.log" 2> "$tmp/ss4rec.err" \
    && "$disim" fly $ss4 --pilot replay "$tmp/ss4.log" 2> "$tmp/ss4.err" && ok \
    || { bad "the landing in sea state 4 was not logged and replayed"; cat "$tmp/ss4rec.err" "$tmp/ss4.err"; }
line=$(grep "fly: replay to [0-9.]* s: from the reference rms" "$tmp/ss4.err")
echo "$line"
echo "$line" | awk '{ for (i = 1; i <= NF; i++) { if ($i == "rms") r = $(i + 1); if ($i == "max" && $(i - 1) == "m,") m = $(i + 1) }
        exit !(r != "" && r + 0 <= 0.26 && m + 0 <= 0.59) }' && ok \
    || bad "the replay in sea state 4 did not track the landing (rms <= 0.26 m, max <= 0.59 m): $line"
# the scenario's [pilot] type = replay flies the same (no --pilot flag)
cat > "$tmp/replay.ini" <<EOF
[scenario]
name = replay_cli
aircraft = $src/scenarios/aircraft/uh60a.ini
ship = $src/scenarios/ships/cg47.ini
[wod]
mode = single
speed_kt = 10
dir_deg = 30
[pilot]
type = replay
log = $tmp/rec.log
EOF
"$disim" fly "$tmp/replay.ini" --db "$tmp/db" --csv "$tmp/sc.csv" 2> "$tmp/sc.err" && cmp -s "$tmp/rep.csv" "$tmp/sc.csv" \
    && ok || { bad "[pilot] type = replay did not fly as --pilot replay"; cat "$tmp/sc.err"; }
# bad logs: each refused, naming the file and what is wrong, nothing written
check_bad() { # NAME LOG PATTERN
    "$disim" fly $args --pilot replay "$2" --csv "$tmp/bad.csv" 2> "$tmp/$1.err" && bad "$1: accepted" \
        || { grep -q "$3" "$tmp/$1.err" && ok || { bad "$1: no reason"; cat "$tmp/$1.err"; }; }
    ls "$tmp"/bad.csv* > /dev/null 2>&1 && bad "$1: a refused run wrote a CSV" || ok
}
check_bad missing "$tmp/none.log" "none.log: cannot read the LCM log"
check_bad not_a_log "$scen" "cg47_uh60a.ini: not an LCM event log"
head -c 100000 "$tmp/rec.log" > "$tmp/cut.log"
check_bad truncated "$tmp/cut.log" "cut.log: event [0-9]* (byte [0-9]*): .*(truncated)"
"$disim" fly "$scen" --fast --duration 0 --wod-speed-kt 0 --wod-dir-deg 0 --db "$tmp/db" --log "$tmp/empty.log" 2> /dev/null
check_bad no_heli_state "$tmp/empty.log" "empty.log: 0 heli_state_t in [0-9]* events"
# bad flags
"$disim" fly $args --pilot replay "$tmp/rec.log" --log "$tmp/x.log" 2> "$tmp/f1.err" && bad "--log accepted" \
    || { grep -q "replay flies headless" "$tmp/f1.err" && ok || bad "--log: no reason"; }
"$disim" fly $args --pilot replay --task "$src/scenarios/tasks/land_uh60a.ini" 2> "$tmp/f2.err" && bad "--task accepted" \
    || { grep -q "or --pilot replay LOG" "$tmp/f2.err" && ok || bad "--pilot replay --task: no reason"; }
"$disim" fly $args --feed-controls 2> "$tmp/f3.err" && bad "--feed-controls alone accepted" \
    || { grep -q "or --pilot replay LOG" "$tmp/f3.err" && ok || bad "--feed-controls: no reason"; }
echo "fly_replay_cli: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
