#!/bin/sh
# disim fly --render DIR: live frames beside the loop (render/live.c). As
# fast as it can, the flight with --render gives the trajectory it gives
# without, byte for byte, and a log of the same size (the renderer reads
# copies); the frames are there, numbered from 000000, and the summary line
# says how many; with ffmpeg, --render-video on writes one MP4 per camera
# instead; bad --render flags are refused (exit 2) naming the flag; a
# renderer that fails (a folder that cannot be made) exits 1 with its
# error after the trajectory is written. Without an ffmpeg that encodes
# H.264 the video check is skipped: the others run, then exit 77 (a
# failure with CI set: tests/skip.sh).
# Usage: fly_render.sh DISIM SOURCE_DIR
set -u
disim=$1 src=$2
tmp=$(mktemp -d /tmp/disim_fly_render_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail=0 pass=0 skipped=""
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $1"; fail=$((fail + 1)); }
args="$src/scenarios/cg47_uh60a.ini --fast --no-lcm --duration 2 --wod-speed-kt 20 --wod-dir-deg -30 --sea-state 4
    --db $tmp/db"
# shellcheck disable=SC2086
"$disim" fly $args --csv "$tmp/a.csv" --log "$tmp/a.lcm" 2> "$tmp/a.log" && ok || { bad "fly failed"; cat "$tmp/a.log"; }
# shellcheck disable=SC2086
"$disim" fly $args --csv "$tmp/b.csv" --log "$tmp/b.lcm" --render "$tmp/frames" --render-size 160x120 \
    --render-cameras deck,overhead 2> "$tmp/b.log" && ok || { bad "fly --render failed"; cat "$tmp/b.log"; }
cmp -s "$tmp/a.csv" "$tmp/b.csv" && ok || bad "--render changed the trajectory"
[ -s "$tmp/a.lcm" ] && [ "$(wc -c < "$tmp/a.lcm")" -eq "$(wc -c < "$tmp/b.lcm")" ] && ok \
    || bad "--render changed the log's size"
[ -f "$tmp/frames/deck_000000.png" ] && [ -f "$tmp/frames/overhead_000000.png" ] && ok \
    || { bad "no frames numbered from 000000"; ls "$tmp/frames"; }
n=$(ls "$tmp/frames" | grep -c '\.png$')
grep -q "fly: rendered $n frames into $tmp/frames" "$tmp/b.log" && ok || { bad "the summary does not say $n frames"; cat "$tmp/b.log"; }
if ffmpeg -hide_banner -encoders 2> /dev/null | grep -q libx264; then
    # shellcheck disable=SC2086
    "$disim" fly $args --render "$tmp/video" --render-size 160x120 --render-video on 2> "$tmp/v.log" \
        && [ -s "$tmp/video/deck.mp4" ] && [ "$(ls "$tmp/video")" = deck.mp4 ] && ok \
        || { bad "--render-video on: no deck.mp4 alone"; cat "$tmp/v.log"; ls "$tmp/video"; }
else
    skipped="no ffmpeg with libx264 on PATH for the --render-video check (go.sh installs it)"
fi
# refusals: exit 2 and the flag named
expect() { # STATUS MESSAGE FLAGS...
    want=$1 msg=$2
    shift 2
    # shellcheck disable=SC2086
    "$disim" fly $args "$@" > "$tmp/e.log" 2>&1
    rc=$?
    [ "$rc" -eq "$want" ] && grep -qF -- "$msg" "$tmp/e.log" && ok \
        || { bad "fly $*: exit $rc (expected $want), message:"; cat "$tmp/e.log"; }
}
expect 2 "need --render DIR" --render-rate 5
expect 2 "--render-rate: expected a number" --render "$tmp/x" --render-rate 0
expect 2 "--render-rate 500: expected at most the loop's rate" --render "$tmp/x" --render-rate 500
expect 2 "--render-size '640by480': expected WIDTHxHEIGHT" --render "$tmp/x" --render-size 640by480
expect 2 "--render-cameras 'deck,bridge'" --render "$tmp/x" --render-cameras deck,bridge
expect 2 "--render-video 'maybe': expected on or off" --render "$tmp/x" --render-video maybe
# the renderer's failure: exit 1, its error, the trajectory written first
: > "$tmp/plain"
expect 1 "$tmp/plain/frames" --csv "$tmp/c.csv" --render "$tmp/plain/frames"
cmp -s "$tmp/a.csv" "$tmp/c.csv" && ok || bad "a failed renderer lost the trajectory"
echo "fly_render: $pass passed, $fail failed"
[ "$fail" -eq 0 ] || exit 1
if [ -n "$skipped" ]; then
    . "$src/tests/skip.sh"
    skip fly_render "$skipped"
fi
