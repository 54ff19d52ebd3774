#!/bin/sh
# disim station --view under Xvfb, fed by a peer: otw_peer publishes one
# fixed state (heli_state_t then ship_state_t of a step, 50 Hz) in a private
# network namespace (UDP multicast on loopback, docs/conventions.md); the
# station draws it from the pilot's eye at 640 x 360 with its scripted
# controls as the source; once it has shown frames, `import -window root`
# takes a screenshot and otw_peer check finds the landing spot, the deck's
# forward corners, the ship's horizon bar and the head-up strip's bands
# where the state puts them (pixel colours at projected positions). The
# station is stopped with SIGTERM: it exits 0, reports its frames, frame
# rate and latency (p50, p99) on stderr, wrote a CSV of its frames, and
# published its controls all along (the peer counts them, no gap in seq).
# Then the window as the station's source (no --script, no --scenario): it
# draws the scene of the peer's run_info_t, its controls start at the
# flight's and reach the peer through the input pipe.
# Skipped (exit 77; a failure with CI set, tests/skip.sh) without Xvfb,
# ImageMagick's import, a network namespace or a disim built with SDL2.
# usage: otw_view.sh DISIM OTW_PEER SRC_DIR
set -u
disim=$1
peer=$2
src=$3
. "$src/tests/skip.sh"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
bad() { echo "FAIL: $*"; fail=1; }

# the refusals first: no window needed
"$disim" station --view sideways --script /dev/null > "$tmp/o" 2> "$tmp/e"
[ $? -eq 2 ] && grep -q "pilot" "$tmp/e" || bad "--view sideways: not refused with the cameras named: $(head -2 "$tmp/e")"
"$disim" station --view-size 640x360 --script /dev/null > "$tmp/o" 2> "$tmp/e"
[ $? -eq 2 ] && grep -q "need --view" "$tmp/e" || bad "--view-size without --view: not refused: $(head -2 "$tmp/e")"
"$disim" station --view --view-size 64by2 > "$tmp/o" 2> "$tmp/e"
[ $? -eq 2 ] && grep -q "expected WIDTHxHEIGHT" "$tmp/e" || bad "--view-size 64by2: not refused: $(head -2 "$tmp/e")"
[ $fail -eq 0 ] || exit 1

if DISPLAY= "$disim" station --view --scenario "$src/scenarios/cg47_uh60a.ini" --duration 0.1 > "$tmp/o" 2> "$tmp/e"; then
    bad "--view without a display: exit 0"
fi
grep -q "built without SDL2" "$tmp/e" && skip otw_view "disim was built without SDL2 (libsdl2-dev)"
grep -q "no window" "$tmp/e" || bad "--view without a display: no 'no window' message: $(head -2 "$tmp/e")"
command -v xvfb-run > /dev/null 2>&1 || skip otw_view "xvfb-run (package xvfb) is missing"
command -v import > /dev/null 2>&1 || skip otw_view "ImageMagick's import (package imagemagick) is missing"
unshare -n true 2> /dev/null || skip otw_view "'unshare -n' is not permitted here (needs root or user namespaces)"
command -v ip > /dev/null 2>&1 || skip otw_view "the 'ip' command (iproute2) is missing"
[ $fail -eq 0 ] || exit 1

W=640 H=360
printf '0,55,45,52,48\n' > "$tmp/hold.csv"
cd "$src" || exit 1
unshare -n sh -c '
ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo || exit 1
disim=$1 peer=$2 tmp=$3 W=$4 H=$5
"$peer" peer 60 "$tmp/ready" "$tmp/stop" > "$tmp/peer.out" 2>&1 & p=$!
i=0
while [ ! -e "$tmp/ready" ] && [ $i -lt 100 ]; do sleep 0.05; i=$((i + 1)); done
xvfb-run -a -s "-screen 0 ${W}x${H}x24" sh -c "
\"$disim\" station --view pilot --view-size ${W}x${H} --view-image ${W}x${H} --script \"$tmp/hold.csv\" --script-absolute --id view-test \
    --scenario scenarios/cg47_uh60a.ini --view-stats \"$tmp/frames.csv\" > \"$tmp/st.out\" 2> \"$tmp/st.err\" & s=\$!
i=0
n=0
while [ \$n -lt 6 ] && [ \$i -lt 600 ]; do
    sleep 0.1; i=\$((i + 1))
    [ -e \"$tmp/frames.csv\" ] && n=\$(wc -l < \"$tmp/frames.csv\")
done
import -window root \"$tmp/shot.png\"
sleep 1
kill -TERM \$s
wait \$s
echo \$? > \"$tmp/st.rc\"
"
touch "$tmp/stop"
wait $p
' sh "$disim" "$peer" "$tmp" $W $H
[ "$(cat "$tmp/st.rc" 2> /dev/null)" = 0 ] || bad "disim station --view: exit $(cat "$tmp/st.rc" 2> /dev/null): $(tail -3 "$tmp/st.err")"
grep "view:" "$tmp/st.err"
grep -q "frames/s.*latency from a state's arrival to the frame on screen p50 [0-9.]* ms, p99 [0-9.]* ms" "$tmp/st.err" ||
    bad "no frame rate and latency report: $(tail -2 "$tmp/st.err")"
n=$(($(wc -l < "$tmp/frames.csv") - 1))
[ "$n" -ge 6 ] || bad "the frames CSV has $n frames, expected at least 6"
head -1 "$tmp/frames.csv" | grep -q "^frame,t_s,arrival_s,draw_start_s,draw_end_s,upload_s,present_s,shown_s,latency_s$" || bad "frames CSV header: $(head -1 "$tmp/frames.csv")"
cat "$tmp/peer.out"
sed -n 2,4p "$tmp/frames.csv"
inputs=$(sed -n 's/^inputs //p' "$tmp/peer.out")
[ "${inputs:-0}" -ge 10 ] || bad "the peer received ${inputs:-no} pilot_input_t from the station, expected at least 10"
[ "$(sed -n 's/^gaps //p' "$tmp/peer.out")" = 0 ] || bad "gaps in the station's seq: $(cat "$tmp/peer.out"
sed -n 2,4p "$tmp/frames.csv")"
[ "$(sed -n 's/^last_coll //p' "$tmp/peer.out")" = 55.000 ] || bad "the station's collective is not the script's 55 %"
if [ -s "$tmp/shot.png" ]; then
    "$peer" check scenarios/cg47_uh60a.ini "$tmp/shot.png" pilot $W $H || bad "the screenshot does not show the state"
else
    bad "no screenshot"
fi

# the window as the source (no --script): its controls start at the
# flight's (57.5 % collective in the peer's states) and reach the station
# through the input pipe; no --scenario: the scene from the peer's
# run_info_t; --duration ends it
rm -f "$tmp/ready" "$tmp/stop"
unshare -n sh -c '
ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo || exit 1
disim=$1 peer=$2 tmp=$3
"$peer" peer 60 "$tmp/ready" "$tmp/stop" scenarios/cg47_uh60a.ini > "$tmp/peer2.out" 2>&1 & p=$!
i=0
while [ ! -e "$tmp/ready" ] && [ $i -lt 100 ]; do sleep 0.05; i=$((i + 1)); done
xvfb-run -a -s "-screen 0 320x180x24" "$disim" station --view chase --view-size 320x180 --id view-window \
    --duration 4 > "$tmp/st2.out" 2> "$tmp/st2.err"
echo $? > "$tmp/st2.rc"
touch "$tmp/stop"
wait $p
' sh "$disim" "$peer" "$tmp"
[ "$(cat "$tmp/st2.rc" 2> /dev/null)" = 0 ] || bad "disim station --view (window source): exit $(cat "$tmp/st2.rc" 2> /dev/null): $(tail -3 "$tmp/st2.err")"
grep -q "(window)" "$tmp/st2.err" || bad "the window is not the station's source: $(head -2 "$tmp/st2.err")"
grep "view:" "$tmp/st2.err"
grep -q "view: [1-9][0-9]* states received, [0-9]* frames drawn, [1-9][0-9]* shown" "$tmp/st2.err" ||
    bad "no frames shown from the scene of the peer's run_info_t: $(grep "view:" "$tmp/st2.err")"
cat "$tmp/peer2.out"
[ "$(sed -n 's/^last_coll //p' "$tmp/peer2.out")" = 57.500 ] ||
    bad "the window's collective did not start at the flight's 57.5 %: $(cat "$tmp/peer2.out")"
[ "$(sed -n 's/^gaps //p' "$tmp/peer2.out")" = 0 ] || bad "gaps in the window station's seq: $(cat "$tmp/peer2.out")"
[ $fail -eq 0 ] && echo "otw_view: passed"
exit $fail
