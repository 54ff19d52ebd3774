#!/bin/sh
# disim shol --method pilot end to end in calm air (--speed-max-kmh 0: no
# airwake field is needed): three directions in sea state 3, three seeds
# per point, the landing task flown at each; every output is written, with
# the columns docs/shol.md gives, one row per direction and per point; the
# sea state reaches the flights; a recorded run given as --task is re-flown
# by the replay pilot; the steady criteria's window comes from the
# scenario's [flown] window_s or --criteria-window-s (the flag over it) and
# reaches the outputs; bad flags and a missing task are refused.
# Usage: shol_pilot_cli.sh DISIM SOURCE_DIR
set -u
disim=$1 src=$2
tmp=$(mktemp -d /tmp/disim_shol_pilot_XXXXXX)
fail=0
scen=$src/tests/shol/data/pilot_cg47.ini
task=$src/scenarios/tasks/land_uh60a.ini
"$disim" shol "$scen" --method pilot --task "$task" --seeds 3 --speed-max-kmh 0 -o "$tmp/out" --db "$tmp/db" \
    > "$tmp/run.csv" 2> "$tmp/run.log" || { echo "the pilot run failed"; cat "$tmp/run.log"; fail=1; }
for f in shol_flown.csv shol_flown_points.csv shol_flown.json shol_polar_flown.png shol_polar_flown.svg report.md shol.csv shol.json; do
    [ -s "$tmp/out/$f" ] || { echo "missing output $f"; fail=1; }
done
[ -d "$tmp/db/fields" ] && [ -n "$(ls "$tmp/db/fields" 2>/dev/null)" ] && { echo "calm air built a field"; fail=1; }
head -1 "$tmp/out/shol_flown.csv" | grep -qx "wod_dir_deg,max_speed_kt,max_speed_kmh,pass_rate_at_max,fail_speed_kt,pass_rate_at_fail,cause,trim_max_speed_kt,trim_limit,band_lo_kmh,band_hi_kmh,band_grid_kmh,band_window_kmh,band_sens_kmh,band_open_above,low_confidence,band_model_kmh,rate_band_lo_kmh,rate_band_hi_kmh,rate_band_open_above" \
    || { echo "bad shol_flown.csv header"; head -1 "$tmp/out/shol_flown.csv"; fail=1; }
head -1 "$tmp/out/shol_flown_points.csv" | grep -qx "wod_dir_deg,speed_kt,speed_kmh,flights,passed,pass_rate,pass,cause,pass_rate_lo,pass_rate_hi,verdict,track_rms_m,track_max_m,tracked" \
    || { echo "bad shol_flown_points.csv header"; head -1 "$tmp/out/shol_flown_points.csv"; fail=1; }
# each point's 90 % Wilson interval and verdict; no tracking error for the automated pilot
[ "$(grep -c ',0\.[0-9]*,[01]\.[0-9]*,\(clear_pass\|undecided\|clear_fail\),nan,nan,$' "$tmp/out/shol_flown_points.csv")" -eq 3 ] \
    || { echo "shol_flown_points.csv: expected each point's interval and verdict"; cat "$tmp/out/shol_flown_points.csv"; fail=1; }
[ "$(wc -l < "$tmp/out/shol_flown.csv")" -eq 4 ] || { echo "shol_flown.csv: expected 3 directions"; fail=1; }
# one point per direction (0 km/h), three flights each
[ "$(grep -c '^[-0-9.]*,0.00,0.0,3,[0-3],' "$tmp/out/shol_flown_points.csv")" -eq 3 ] \
    || { echo "shol_flown_points.csv: expected three 0 km/h points of 3 flights"; cat "$tmp/out/shol_flown_points.csv"; fail=1; }
grep -q "sea state 3" "$tmp/out/report.md" && grep -q "3 seeds per point" "$tmp/run.log" \
    || { echo "the sea state or the seeds did not reach the flights"; fail=1; }
grep -q '^| red 30 | 0.0 | none |' "$tmp/out/report.md" || { echo "report.md: no red 30 row"; fail=1; }
[ "$(head -1 "$tmp/run.csv")" = "wod_dir_deg,trim_max_speed_kt,flown_max_speed_kt,pass_rate_at_fail,cause" ] \
    && [ "$(wc -l < "$tmp/run.csv")" -eq 4 ] || { echo "stdout: expected a header and 3 rows"; cat "$tmp/run.csv"; fail=1; }
# quiet in a log: no progress lines but the last
[ "$(grep -c '^flown: ' "$tmp/run.log")" -eq 1 ] || { echo "progress lines in a log"; fail=1; }
# --task LOG: the replay pilot re-flies a recorded 5 s hover (disim fly --log)
"$disim" fly "$src/scenarios/cg47_uh60a.ini" --fast --duration 5 --wod-speed-kt 0 --wod-dir-deg 0 --db "$tmp/db" \
    --log "$tmp/rec.log" 2> "$tmp/rec.err" || { echo "the recorded run failed"; cat "$tmp/rec.err"; fail=1; }
"$disim" shol "$scen" --method pilot --task "$tmp/rec.log" --seeds 2 --speed-max-kmh 0 -o "$tmp/rep" --db "$tmp/db" \
    > /dev/null 2> "$tmp/rep.log" || { echo "the replay run failed"; cat "$tmp/rep.log"; fail=1; }
grep -q "the replay pilot re-flies .*rec.log, 2 seeds per point" "$tmp/rep.log" && grep -q "replay pilot, recorded run" "$tmp/rep/report.md" \
    && grep -q '"flights": 6,' "$tmp/rep/shol_flown.json" && grep -q '"flown_s": 30.0,' "$tmp/rep/shol_flown.json" \
    || { echo "the replay pilot did not fly the log's 5 s at each point"; cat "$tmp/rep.log"; fail=1; }
# the recording judged by the criteria: the calm hover is within every limit;
# with the pitch limit at 5 deg (the UH-60A hovers at about 6 deg) it is not
grep -q "The recording itself, judged by the same criteria up to its touchdown: within every limit." "$tmp/rep/report.md" \
    || { echo "the report does not judge the recording"; fail=1; }
sed 's/^pitch_deg = .*/pitch_deg = 5/' "$src/scenarios/aircraft/uh60a.ini" > "$tmp/uh60a_p5.ini"
sed "s|^aircraft = .*|aircraft = $tmp/uh60a_p5.ini|; s|^ship = .*|ship = $src/scenarios/ships/cg47.ini|" "$scen" > "$tmp/p5.ini"
"$disim" shol "$tmp/p5.ini" --method pilot --task "$tmp/rec.log" --seeds 1 --speed-max-kmh 0 -o "$tmp/rep5" --db "$tmp/db" \
    > /dev/null 2> "$tmp/rep5.log" || { echo "the replay run with pitch 5 deg failed"; cat "$tmp/rep5.log"; fail=1; }
grep -q "shol: the recording judged by the criteria: pitch (3 s mean) in hover at 3.02 s" "$tmp/rep5.log" \
    && grep -q "The recording itself, judged by the same criteria up to its touchdown: \*\*pitch (3 s mean) in hover at 3.02 s\*\*" "$tmp/rep5/report.md" \
    || { echo "a recording beyond the pitch limit is not named"; cat "$tmp/rep5.log"; fail=1; }
# the replay's tracking error beside the criteria's result: rms and max from the recording, flights within 2 m
[ "$(grep -c ',[0-9]*\.[0-9]*,[0-9]*\.[0-9]*,[0-2]$' "$tmp/rep/shol_flown_points.csv")" -eq 3 ] && grep -q "could not track" "$tmp/rep/report.md" \
    || { echo "the replay's tracking error is not in the points"; cat "$tmp/rep/shol_flown_points.csv"; fail=1; }
# --feed-controls: the recorded controls fed forward too, said in the report; refused with a task file
"$disim" shol "$scen" --method pilot --task "$tmp/rec.log" --feed-controls --seeds 1 --speed-max-kmh 0 -o "$tmp/repf" \
    --db "$tmp/db" > /dev/null 2> "$tmp/repf.log" && grep -q "rec.log (its controls fed forward)" "$tmp/repf/report.md" \
    || { echo "--feed-controls did not reach the replay pilot's run"; cat "$tmp/repf.log"; fail=1; }
"$disim" shol "$scen" --method pilot --task "$task" --feed-controls > /dev/null 2> "$tmp/bad.log"
[ $? -eq 2 ] && grep -q "feed-controls: the replay pilot's" "$tmp/bad.log" || { echo "--feed-controls with a task accepted"; fail=1; }
# the steady criteria's window: the scenario's [flown] window_s, the flag over it
sed "s#\.\./\.\./\.\./#$src/#" "$scen" > "$tmp/win.ini" && printf '\n[flown]\nwindow_s = 0.5\n' >> "$tmp/win.ini"
"$disim" shol "$tmp/win.ini" --method pilot --task "$task" --seeds 1 --speed-max-kmh 0 -o "$tmp/win" --db "$tmp/db" \
    > /dev/null 2> "$tmp/win.log" || { echo "the [flown] window_s run failed"; cat "$tmp/win.log"; fail=1; }
grep -q '"criteria_window_s": 0.500, "transient_frac": 0.500' "$tmp/win/shol_flown.json" \
    && grep -q "running mean over the last 0.5 s" "$tmp/win/report.md" \
    || { echo "[flown] window_s = 0.5 did not reach the flights' judgement"; fail=1; }
grep -q '"criteria_window_s": 3.000' "$tmp/out/shol_flown.json" || { echo "the default window is not 3 s"; fail=1; }
"$disim" shol "$tmp/win.ini" --method pilot --task "$task" --seeds 1 --speed-max-kmh 0 --criteria-window-s 0 \
    -o "$tmp/win0" --db "$tmp/db" > /dev/null 2> "$tmp/win0.log" || { echo "the --criteria-window-s 0 run failed"; fail=1; }
grep -q '"criteria_window_s": 0.000' "$tmp/win0/shol_flown.json" && grep -q "every step's values" "$tmp/win0/report.md" \
    || { echo "--criteria-window-s 0 did not override [flown] window_s"; fail=1; }
sed -i 's/^window_s = 0.5$/window_s = 99/' "$tmp/win.ini"
"$disim" shol "$tmp/win.ini" --method pilot --speed-max-kmh 0 -o "$tmp/win1" --db "$tmp/db" > /dev/null 2> "$tmp/bad.log"
[ $? -eq 1 ] && grep -q "win.ini:[0-9]*: \[flown\] window_s.*60" "$tmp/bad.log" || { echo "[flown] window_s = 99 accepted"; cat "$tmp/bad.log"; fail=1; }
"$disim" shol "$scen" --method pilot --criteria-window-s 61 > /dev/null 2> "$tmp/bad.log"
[ $? -eq 2 ] && grep -q "\-\-criteria-window-s" "$tmp/bad.log" || { echo "--criteria-window-s 61 accepted"; fail=1; }
"$disim" shol "$scen" --criteria-window-s 3 > /dev/null 2> "$tmp/bad.log"
[ $? -eq 2 ] && grep -q "go with --method pilot" "$tmp/bad.log" || { echo "--criteria-window-s without --method pilot accepted"; fail=1; }
# Bad flags and inputs.
"$disim" shol "$scen" --method fly > /dev/null 2> "$tmp/bad.log"
[ $? -eq 2 ] && grep -q "expected trim or pilot" "$tmp/bad.log" || { echo "--method fly accepted"; fail=1; }
"$disim" shol "$scen" --method pilot --seeds 0 > /dev/null 2> "$tmp/bad.log"
[ $? -eq 2 ] && grep -q "\-\-seeds" "$tmp/bad.log" || { echo "--seeds 0 accepted"; fail=1; }
"$disim" shol "$scen" --method pilot --seeds 2.5 > /dev/null 2> "$tmp/bad.log"
[ $? -eq 2 ] && grep -q "whole number" "$tmp/bad.log" || { echo "--seeds 2.5 accepted"; fail=1; }
"$disim" shol "$scen" --task "$task" > /dev/null 2> "$tmp/bad.log"
[ $? -eq 2 ] && grep -q "go with --method pilot" "$tmp/bad.log" || { echo "--task without --method pilot accepted"; fail=1; }
"$disim" shol "$scen" --method pilot --task "$tmp/none.ini" --speed-max-kmh 0 -o "$tmp/out2" --db "$tmp/db" > /dev/null 2> "$tmp/bad.log"
[ $? -eq 1 ] && grep -q "none.ini" "$tmp/bad.log" && [ ! -e "$tmp/out2/shol_flown.csv" ] || { echo "a missing task accepted"; cat "$tmp/bad.log"; fail=1; }
# the trim method still refuses a sea state
"$disim" shol "$scen" --speed-max-kmh 0 -o "$tmp/out3" --db "$tmp/db" > /dev/null 2> "$tmp/bad.log"
[ $? -eq 1 ] && grep -q "state = 3: the candidate SHOL trims" "$tmp/bad.log" || { echo "the trim method accepted a sea state"; fail=1; }
rm -rf "$tmp"
[ $fail -eq 0 ] && echo "shol_pilot_cli: ok"
exit $fail
