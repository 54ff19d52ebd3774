#!/bin/sh
# disim fly --pilot auto --task FILE: the automated pilot flies a task
# headless (sim/pilot_auto.c): the station-keeping task moved 3 m to
# starboard of the scenario's hover is met (desired) and the CSV ends
# within 1 m of the target; the landing task in sea state 4 touches down
# within its desired tolerances; the port-side deck landing starts
# alongside, lands within 1 m below 2 m/s and writes its result (CSV,
# JSON) beside the trajectory or at --task-result, and with --log logs
# the run without changing it; bad flags and a bad task file are
# refused, naming what, with nothing written.
# Usage: fly_auto_cli.sh DISIM SOURCE_DIR
set -u
disim=$1 src=$2
tmp=$(mktemp -d /tmp/disim_fly_auto_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail=0 pass=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $1"; fail=$((fail + 1)); }
sed 's/^target_S_m = .*/target_S_m = 0,3,-6/' "$src/scenarios/tasks/station_keep.ini" > "$tmp/task.ini"
args="$src/scenarios/cg47_uh60a.ini --wod-speed-kt 0 --wod-dir-deg 0 --db $tmp/db"
"$disim" fly $args --pilot auto --task "$tmp/task.ini" --csv "$tmp/auto.csv" 2> "$tmp/auto.log" && ok \
    || { bad "fly --pilot auto failed"; cat "$tmp/auto.log"; }
grep -q "task desired at 80.0 s" "$tmp/auto.log" && ok || { bad "the task was not met (desired)"; cat "$tmp/auto.log"; }
[ "$(wc -l < "$tmp/auto.csv")" -eq 4002 ] && ok || bad "expected a header and 4001 rows at 50 Hz over the task's 80 s"
tail -1 "$tmp/auto.csv" | awk -F, '{d = ($3 - 3) * ($3 - 3) + $2 * $2; exit !(d < 1 && $4 > -7 && $4 < -5)}' && ok \
    || { bad "the flight did not end within 1 m of the target"; tail -1 "$tmp/auto.csv"; }
"$disim" fly $args --pilot auto --task "$tmp/task.ini" --duration 2 2> "$tmp/d.log" && grep -q "for 2 s" "$tmp/d.log" \
    && ok || bad "--duration did not override the task's length"
# the landing task in sea state 4: the run ends at touchdown, within the desired touchdown tolerances
"$disim" fly $args --sea-state 4 --pilot auto --task "$src/scenarios/tasks/land_uh60a.ini" 2> "$tmp/land.log" \
    && grep -q "touchdown desired at" "$tmp/land.log" && ok || { bad "the landing was not within desired"; cat "$tmp/land.log"; }
# the port-side deck landing (scenarios/tasks/land_port.ini) in sea state 4 and 25 kt: it starts alongside
# to port (the first CSV row 10 m outboard of the CG-47's deck edge at y = -7 m), touches down within 1 m
# of the spot below 2 m/s, and the task's result is written beside the CSV as CSV and JSON
"$disim" fly "$src/scenarios/cg47_uh60a.ini" --wod-speed-kt 25 --wod-dir-deg 0 --db "$tmp/db" --sea-state 4 \
    --pilot auto --task "$src/scenarios/tasks/land_port.ini" --csv "$tmp/port.csv" 2> "$tmp/port.log" && ok \
    || { bad "the port-side landing failed"; cat "$tmp/port.log"; }
sed -n 2p "$tmp/port.csv" | awk -F, '{exit !($3 > -17.5 && $3 < -16.5)}' && ok \
    || { bad "the port-side landing did not start alongside"; sed -n 2p "$tmp/port.csv"; }
[ -f "$tmp/port_task.csv" ] && [ -f "$tmp/port_task.json" ] && ok || bad "no task result beside the CSV"
awk -F, 'NR == 1 {for (i = 1; i <= NF; i++) c[$i] = i} NR == 2 {s = $c["sink_mps"]; d = $c["dist_spot_m"];
    exit !(s > 0 && s < 2 && d < 1 && $c["touched"] == 1 && $c["descent_grade"] != "")}' "$tmp/port_task.csv" && ok \
    || { bad "the result CSV: not down within 1 m below 2 m/s"; cat "$tmp/port_task.csv"; }
grep -q '"sink_mps": ' "$tmp/port_task.json" && grep -q '"name": "traverse"' "$tmp/port_task.json" && ok \
    || bad "the result JSON lacks the sink rate or the traverse phase"
# --log: the same landing logged through the loop (the pilot a station "auto"): the trajectory is the
# one flown without the log, byte for byte, and the log holds its run_info_t and its states
"$disim" fly "$src/scenarios/cg47_uh60a.ini" --wod-speed-kt 25 --wod-dir-deg 0 --db "$tmp/db" --sea-state 4 \
    --pilot auto --task "$src/scenarios/tasks/land_port.ini" --csv "$tmp/portlog.csv" --log "$tmp/port.lcm" \
    2> "$tmp/portlog.log" && grep -q "the run logged to $tmp/port.lcm" "$tmp/portlog.log" && ok \
    || { bad "the logged landing failed"; cat "$tmp/portlog.log"; }
cmp -s "$tmp/port.csv" "$tmp/portlog.csv" && ok || bad "--log changed the automated pilot's trajectory"
grep -q DISIM_RUN_INFO "$tmp/port.lcm" && grep -q DISIM_HELI_STATE "$tmp/port.lcm" && ok \
    || bad "the log lacks run_info_t or heli_state_t"
# --realtime with LCM (in-process memq://): paced, the pilot's inputs published and logged once a step
# (200 in 1 s at 200 Hz: not listened back to), the same trajectory as --fast
"$disim" fly $args --pilot auto --task "$tmp/task.ini" --duration 1 --realtime --lcm memq:// --log "$tmp/rt.lcm" \
    --csv "$tmp/rt.csv" 2> "$tmp/rt.log" && ok || { bad "--realtime --lcm failed"; cat "$tmp/rt.log"; }
[ "$(grep -a -o DISIM_PILOT_INPUT "$tmp/rt.lcm" | wc -l)" -eq 200 ] && ok \
    || bad "expected 200 pilot inputs in the real-time log, got $(grep -a -o DISIM_PILOT_INPUT "$tmp/rt.lcm" | wc -l)"
"$disim" fly $args --pilot auto --task "$tmp/task.ini" --duration 1 --csv "$tmp/fast.csv" 2> /dev/null
cmp -s "$tmp/rt.csv" "$tmp/fast.csv" && ok || bad "--realtime flew another trajectory than --fast"
ls "$tmp"/*.tmp* > /dev/null 2>&1 && bad "a temporary file was left" || ok
"$disim" fly $args --pilot auto --task "$tmp/task.ini" --duration 2 --task-result "$tmp/named" 2> /dev/null \
    && [ -f "$tmp/named.csv" ] && [ -f "$tmp/named.json" ] && ok || bad "--task-result PREFIX wrote no PREFIX.csv, .json"
"$disim" fly $args --task-result "$tmp/x" 2> "$tmp/e5.log" && bad "--task-result without --pilot auto accepted" \
    || { grep -q "task-result: expected --pilot auto" "$tmp/e5.log" && ok || bad "--task-result: no reason"; }
# refused: another pilot, no task, stations, a bad task file (its line named), --log with the replay pilot
"$disim" fly $args --pilot replay --task "$tmp/task.ini" 2> "$tmp/e1.log" && bad "--pilot replay accepted" \
    || { grep -q "expected --pilot auto with --task FILE" "$tmp/e1.log" && ok || bad "--pilot replay: no reason"; }
"$disim" fly $args --pilot auto 2> /dev/null && bad "--pilot auto without --task accepted" || ok
"$disim" fly $args --pilot auto --task "$tmp/task.ini" --stations a,b 2> "$tmp/e3.log" && bad "--stations accepted" \
    || { grep -q "stations do not apply (the automated pilot flies)" "$tmp/e3.log" && ok || bad "--stations: no reason"; }
"$disim" fly $args --pilot replay "$tmp/port.lcm" --log "$tmp/r.lcm" 2> "$tmp/e6.log" && bad "replay --log accepted" \
    || { grep -q "replay flies headless" "$tmp/e6.log" && ok || bad "replay --log: no reason"; }
"$disim" fly $args --pilot auto --task "$tmp/task.ini" --duration 2 --sas off --csv "$tmp/off.csv" 2> /dev/null && ok \
    || bad "--sas off refused"
"$disim" fly $args --pilot auto --task "$tmp/task.ini" --duration 2 --csv "$tmp/on.csv" 2> /dev/null
cmp -s "$tmp/off.csv" "$tmp/on.csv" && bad "--sas off flew as the SAS on" || ok
"$disim" fly $args --sas maybe 2> "$tmp/e7.log"; [ $? -eq 2 ] && grep -q "sas 'maybe': expected on or off" "$tmp/e7.log" \
    && ok || bad "--sas maybe: not refused"
sed 's/^duration_s = .*/duration_s = -5/' "$tmp/task.ini" > "$tmp/bad.ini"
"$disim" fly $args --pilot auto --task "$tmp/bad.ini" --csv "$tmp/bad.csv" 2> "$tmp/e4.log" && bad "a bad task accepted" \
    || { grep -q "bad.ini:[0-9]*: \[task\] duration_s" "$tmp/e4.log" && ok || { bad "bad task: no file:line"; cat "$tmp/e4.log"; }; }
ls "$tmp"/bad.csv* > /dev/null 2>&1 && bad "a refused run wrote a CSV" || ok
echo "fly_auto_cli: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
