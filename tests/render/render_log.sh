#!/bin/sh
# disim render LOG: a landing flown by the automated pilot and logged
# (disim fly --pilot auto --log) drawn from its log for every camera: the
# frames and, where ffmpeg is installed, a video per camera; the same log
# gives the same frames twice; the HUD changes the frame; a log with no
# run information is drawn with --scenario; bad logs (not a log, truncated,
# no states) and bad flags are refused, naming what, with no video left.
# Without ffmpeg (and its ffprobe) the video checks are skipped: the others
# run, then exit 77 (a failure with CI set: tests/skip.sh).
# Usage: render_log.sh DISIM SOURCE_DIR
set -u
disim=$1 src=$2
tmp=$(mktemp -d /tmp/disim_render_log_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail=0 pass=0 skipped=""
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $1"; fail=$((fail + 1)); }
# a short deck landing in calm air and sea state 4 (no airwake field needed), logged
"$disim" fly "$src/scenarios/cg47_uh60a.ini" --wod-speed-kt 0 --wod-dir-deg 0 --db "$tmp/db" --sea-state 4 \
    --pilot auto --task "$src/scenarios/tasks/land_port.ini" --duration 8 --log "$tmp/run.lcm" 2> "$tmp/fly.log" \
    && [ -s "$tmp/run.lcm" ] && ok || { bad "the landing was not logged"; cat "$tmp/fly.log"; }
args="--size 96x64 --fps 2 --from 2 --to 4"
"$disim" render "$tmp/run.lcm" -o "$tmp/a" --camera all $args --video off > "$tmp/r.out" 2> "$tmp/r.log" && ok \
    || { bad "render failed"; cat "$tmp/r.log"; }
for c in pilot deck chase overhead; do
    [ "$(ls "$tmp/a"/${c}_*.png 2> /dev/null | wc -l)" -eq 5 ] && ok || bad "$c: expected 5 frames (2 s at 2 frames/s)"
done
"$disim" render "$tmp/run.lcm" -o "$tmp/b" --camera all $args --video off > /dev/null 2>&1
same=1
for f in "$tmp/a"/*.png; do cmp -s "$f" "$tmp/b/$(basename "$f")" || same=0; done
[ "$same" -eq 1 ] && ok || bad "the same log gave different frames"
"$disim" render "$tmp/run.lcm" -o "$tmp/h" --camera deck $args --video off --overlay hud > /dev/null 2>&1 \
    && ! cmp -s "$tmp/a/deck_000000.png" "$tmp/h/deck_000000.png" && ok || bad "--overlay hud left the frame unchanged"
if command -v ffmpeg > /dev/null 2>&1; then
    "$disim" render "$tmp/run.lcm" -o "$tmp/v" --camera deck,chase $args --frames off > /dev/null 2> "$tmp/v.log" \
        && [ -s "$tmp/v/deck.mp4" ] && [ -s "$tmp/v/chase.mp4" ] && ok || { bad "no videos"; cat "$tmp/v.log"; }
    if command -v ffprobe > /dev/null 2>&1; then
        n=$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames -of csv=p=0 \
            "$tmp/v/deck.mp4")
        [ "$n" = 5 ] && ok || bad "deck.mp4 has $n frames, expected 5"
    else
        skipped="no ffprobe to count the video's frames (it comes with ffmpeg, which go.sh installs)"
    fi
    ls "$tmp/v" | grep -q tmp && bad "a temporary video was left" || ok
else
    skipped="ffmpeg not installed: the video checks (go.sh installs it)"
fi
# refusals
"$disim" render "$src/CMakeLists.txt" -o "$tmp/x" 2> "$tmp/e1.log" && bad "not a log accepted" \
    || { grep -q "not an LCM event log" "$tmp/e1.log" && ok || { bad "not a log: no reason"; cat "$tmp/e1.log"; }; }
size=$(wc -c < "$tmp/run.lcm")
head -c $((size - 100)) "$tmp/run.lcm" > "$tmp/trunc.lcm"
"$disim" render "$tmp/trunc.lcm" -o "$tmp/x" 2> "$tmp/e2.log" && bad "a truncated log accepted" \
    || { grep -q "truncated" "$tmp/e2.log" && ok || { bad "truncated: no reason"; cat "$tmp/e2.log"; }; }
# the first event alone (run_info_t): no states. Its length from the header (channel and data lengths, bytes 20-27)
hdr=$(od -An -tu1 -j20 -N8 "$tmp/run.lcm" | tr -s ' ')
set -- $hdr
clen=$(( ($1 << 24) + ($2 << 16) + ($3 << 8) + $4 ))
dlen=$(( ($5 << 24) + ($6 << 16) + ($7 << 8) + $8 ))
head -c $((28 + clen + dlen)) "$tmp/run.lcm" > "$tmp/nostate.lcm"
"$disim" render "$tmp/nostate.lcm" -o "$tmp/x" 2> "$tmp/e3.log" && bad "a log with no states accepted" \
    || { grep -q "0 heli_state_t in 1 events" "$tmp/e3.log" && ok || { bad "no states: no reason"; cat "$tmp/e3.log"; }; }
# the log without its first event (run_info_t), as an older disim wrote it: refused without --scenario;
# with it, drawn, and the sea drawn flat with a warning, since the run flew sea state 4 (--sea-state) and
# the scenario says calm: the rebuilt seaway does not move the ship as the log does
tail -c +$((28 + clen + dlen + 1)) "$tmp/run.lcm" > "$tmp/noinfo.lcm"
"$disim" render "$tmp/noinfo.lcm" -o "$tmp/x" 2> "$tmp/e8.log" && bad "no run_info_t accepted" \
    || { grep -q "no run_info_t in the log" "$tmp/e8.log" && ok || { bad "no run_info_t: no reason"; cat "$tmp/e8.log"; }; }
"$disim" render "$tmp/noinfo.lcm" -o "$tmp/s" --scenario "$src/scenarios/cg47_uh60a.ini" $args --camera deck \
    --video off > /dev/null 2> "$tmp/s.log" && [ -f "$tmp/s/deck_000004.png" ] && ok \
    || { bad "--scenario did not draw the log"; cat "$tmp/s.log"; }
grep -q "the sea is drawn flat" "$tmp/s.log" && ok || { bad "no warning of a seaway that disagrees"; cat "$tmp/s.log"; }
grep -q "the sea is drawn flat" "$tmp/r.log" && bad "the run's own seaway was refused" || ok
"$disim" render "$tmp/run.lcm" -o "$tmp/x" --camera cockpit 2> "$tmp/e4.log"; [ $? -eq 2 ] \
    && grep -q "camera 'cockpit'" "$tmp/e4.log" && ok || { bad "--camera cockpit: not refused with its name"; cat "$tmp/e4.log"; }
"$disim" render "$tmp/run.lcm" -o "$tmp/x" --overlay smoke 2> "$tmp/e5.log"; [ $? -eq 2 ] \
    && grep -q "smoke" "$tmp/e5.log" && ok || { bad "--overlay smoke: not refused"; cat "$tmp/e5.log"; }
"$disim" render "$tmp/run.lcm" -o "$tmp/x" --from 50 --to 60 2> "$tmp/e6.log" && bad "--from past the end accepted" \
    || { grep -q "outside the log" "$tmp/e6.log" && ok || { bad "--from: no reason"; cat "$tmp/e6.log"; }; }
"$disim" render "$src/scenarios/cg47_uh60a.ini" -o "$tmp/x.png" --camera deck 2> "$tmp/e7.log"; [ $? -eq 2 ] \
    && grep -q "are for a log" "$tmp/e7.log" && ok || { bad "a scenario with --camera: not refused"; cat "$tmp/e7.log"; }
[ -e "$tmp/x" ] && [ -n "$(ls "$tmp/x" 2> /dev/null)" ] && bad "a refused render wrote files" || ok
echo "render_log: $pass passed, $fail failed"
[ "$fail" -eq 0 ] || exit 1
if [ -n "$skipped" ]; then
    . "$src/tests/skip.sh"
    skip render_log "$skipped"
fi
